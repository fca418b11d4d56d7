#include "budget_slam/report/MapScene.h"

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/opengl/CEllipsoid2D.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CText.h>
#include <mrpt/opengl/stock_objects.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/Gzip.h"
#include "budget_slam/core/MrptPose.h"
#include "budget_slam/core/Text.h"

namespace budget_slam::report {

using namespace mrpt::opengl;

namespace {

/// Heights above the grid [m], so that lines and points are not hidden in the grid's plane.
constexpr float kZPath = 0.02f, kZDropped = 0.03f, kZLandmarks = 0.05f;

/// Half the arm of a dropped landmark's cross [m], relative to the map's extent.
constexpr double kCrossFraction = 0.006;

struct Bounds {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  void add(double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  bool empty() const { return !(x0 <= x1); }
};

/// Grid spacing of 1, 2 or 5 times a power of ten giving about 10-25 cells over `extent` [m].
double niceSpacing(double extent) {
  const double raw = std::max(extent, 1e-3) / 15.0;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (raw <= m * p) return m * p;
  return 10 * p;
}

CSetOfLines::Ptr polyline(const std::vector<Pose2>& poses, const char* name, float r, float g,
                          float b, float width) {
  auto lines = CSetOfLines::Create();
  lines->setName(name);
  lines->setColor(r, g, b);
  lines->setLineWidth(width);
  for (std::size_t i = 1; i < poses.size(); ++i)
    lines->appendLine(poses[i - 1].x, poses[i - 1].y, kZPath, poses[i].x, poses[i].y, kZPath);
  return lines;
}

}  // namespace

std::string scene_names::keptLandmark(long long id, int cluster) {
  return "landmark " + std::to_string(id) +
         (cluster >= 0 ? ", coverage cluster " + std::to_string(cluster) : std::string());
}

COpenGLScene::Ptr buildMapScene(const MapContent& c, const Pose2& robot) {
  Bounds b;
  for (const auto& p : c.trajectory) b.add(p.x, p.y);
  for (const auto& p : c.ground_truth_path) b.add(p.x, p.y);
  for (const auto& l : c.kept) b.add(l.mean.x(), l.mean.y());
  for (const auto& d : c.dropped) b.add(d.x(), d.y());
  for (const auto& g : c.ground_truth_landmarks) b.add(g.x(), g.y());
  b.add(robot.x, robot.y);
  if (b.empty()) b.add(0, 0);
  const double extent = std::max({b.x1 - b.x0, b.y1 - b.y0, 1.0});
  const double spacing = niceSpacing(extent);

  auto scene_ptr = COpenGLScene::Create();
  COpenGLScene& scene = *scene_ptr;
  {
    const double gx0 = std::floor(b.x0 / spacing - 1) * spacing,
                 gx1 = std::ceil(b.x1 / spacing + 1) * spacing,
                 gy0 = std::floor(b.y0 / spacing - 1) * spacing,
                 gy1 = std::ceil(b.y1 / spacing + 1) * spacing;
    auto grid = CGridPlaneXY::Create(gx0, gx1, gy0, gy1, 0, spacing, 1.0f);
    grid->setName(scene_names::kGrid);
    grid->setColor(0.82f, 0.82f, 0.82f);
    scene.insert(grid);
  }
  {
    auto title = CText::Create(c.title);
    title->setName(scene_names::kTitle);
    title->setColor(0.1f, 0.1f, 0.1f);
    title->setLocation(b.x0, b.y1 + 0.06 * extent, 0);
    scene.insert(title);
  }

  if (!c.ground_truth_landmarks.empty()) {
    auto gt = CPointCloud::Create();
    gt->setName(scene_names::kGroundTruthLandmarks);
    gt->setColor(0.55f, 0.55f, 0.55f);
    gt->setPointSize(4.0f);
    for (const auto& g : c.ground_truth_landmarks) gt->insertPoint(g.x(), g.y(), 0.01f);
    scene.insert(gt);
  }
  if (!c.ground_truth_path.empty())
    scene.insert(polyline(c.ground_truth_path, scene_names::kGroundTruthPath, 0, 0, 0, 1.5f));
  // The map figure's blue path.
  const auto path = map_colours::kPathGood;
  scene.insert(polyline(c.trajectory, scene_names::kTrajectory, static_cast<float>(path.r),
                        static_cast<float>(path.g), static_cast<float>(path.b), 2.5f));

  {
    auto dropped = CSetOfLines::Create();
    dropped->setName(scene_names::kDropped);
    const auto grey = map_colours::kDropped;  // the map figure's dropped landmarks
    dropped->setColor(static_cast<float>(grey.r), static_cast<float>(grey.g),
                      static_cast<float>(grey.b));
    dropped->setLineWidth(1.5f);
    const double h = kCrossFraction * extent;
    for (const auto& d : c.dropped) {
      dropped->appendLine(d.x() - h, d.y() - h, kZDropped, d.x() + h, d.y() + h, kZDropped);
      dropped->appendLine(d.x() - h, d.y() + h, kZDropped, d.x() + h, d.y() - h, kZDropped);
    }
    scene.insert(dropped);
  }

  {
    auto kept = CSetOfObjects::Create();
    kept->setName(scene_names::kKept);
    auto centres = CPointCloudColoured::Create();
    centres->setName(scene_names::kKeptCentres);
    centres->setPointSize(9.0f);
    for (std::size_t i = 0; i < c.kept.size(); ++i) {
      const auto& l = c.kept[i];
      const int cluster = i < c.cluster_of_kept.size() ? c.cluster_of_kept[i] : -1;
      const auto rgb = cluster >= 0 ? clusterRgb(static_cast<std::size_t>(cluster))
                                    : std::array<std::uint8_t, 3>{40, 150, 40};
      auto e = CEllipsoid2D::Create();
      e->setName(scene_names::keptLandmark(static_cast<long long>(l.id), cluster));
      mrpt::math::CMatrixDouble22 cov;
      cov(0, 0) = l.cov(0, 0), cov(0, 1) = l.cov(0, 1), cov(1, 0) = l.cov(1, 0),
             cov(1, 1) = l.cov(1, 1);
      e->setCovMatrix(cov);
      e->setQuantiles(2.0f);  // the 2-sigma ellipse, as map.png
      e->setLineWidth(2.0f);
      e->setColor_u8(rgb[0], rgb[1], rgb[2]);
      e->setLocation(l.mean.x(), l.mean.y(), kZLandmarks);
      kept->insert(e);
      centres->push_back(static_cast<float>(l.mean.x()), static_cast<float>(l.mean.y()),
                         kZLandmarks, rgb[0] / 255.f, rgb[1] / 255.f, rgb[2] / 255.f);
    }
    scene.insert(kept);
    scene.insert(centres);
  }

  {
    auto r = stock_objects::RobotPioneer();
    r->setName(scene_names::kRobot);
    r->setPose(toTPose2D(robot));
    // The Pioneer model is about 0.5 m long; scaled so that it shows on maps of any size.
    const float s = static_cast<float>(std::max(1.0, extent / 40.0));
    r->setScale(s);
    scene.insert(r);
  }

  // White like map.png; looking at the map's centre from the south, 45 degrees up, the whole map
  // in view for viewers that take the scene's camera (SceneViewer3D starts with its own).
  scene.getViewport()->setCustomBackgroundColor(mrpt::img::TColorf(1, 1, 1));
  auto& cam = scene.getViewport()->getCamera();
  cam.setPointingAt(0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1), 0);
  cam.setZoomDistance(static_cast<float>(1.4 * extent));
  cam.setAzimuthDegrees(-90);
  cam.setElevationDegrees(45);
  return scene_ptr;
}

void writeMapScene(const std::string& path, const MapContent& content, const Pose2& robot) {
  const auto scene = buildMapScene(content, robot);
  // The bytes COpenGLScene::saveToFile writes (the serialized scene, gzip-compressed), made in
  // memory (zlib, no temporary file) and written with a checked atomic write: a full disk is an
  // error naming the file and never leaves a torn scene behind.
  std::string plain;
  try {
    mrpt::io::CMemoryStream mem;
    auto arch = mrpt::serialization::archiveFrom(mem);
    arch << *scene;
    plain.assign(static_cast<const char*>(mem.getRawBufferData()), mem.getTotalBytesCount());
  } catch (const std::exception& e) {
    throw Error("cannot write '" + path + "' (" + exceptionLine(e) + ")");
  }
  writeFileAtomically(path, gzipBytes(plain, 1));
}

}  // namespace budget_slam::report
