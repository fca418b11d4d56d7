#pragma once
#include <mrpt/opengl/COpenGLScene.h>

#include <string>

#include "budget_slam/core/Pose2.h"
#include "budget_slam/report/Pictures.h"

namespace budget_slam::report {

/// Names of the objects of map.3Dscene, for viewers and for scripts that load the scene
/// (COpenGLScene::getByName). docs/OUTPUTS.md describes what each looks like.
namespace scene_names {
constexpr const char* kGrid = "grid";                                ///< CGridPlaneXY, z = 0
constexpr const char* kTitle = "title";                              ///< CText, the map.png title
constexpr const char* kTrajectory = "estimated trajectory";          ///< CSetOfLines, a segment a
                                                                     ///< pair of consecutive poses
constexpr const char* kGroundTruthPath = "ground truth trajectory";  ///< CSetOfLines
constexpr const char* kGroundTruthLandmarks = "ground truth landmarks";  ///< CPointCloud
constexpr const char* kKept = "kept landmarks";  ///< CSetOfObjects of one CEllipsoid2D a landmark
constexpr const char* kKeptCentres = "kept landmark centres";  ///< CPointCloudColoured
constexpr const char* kDropped = "dropped landmarks";  ///< CSetOfLines, an X (2 segments) a drop
constexpr const char* kRobot = "robot";                ///< CSetOfObjects, the last pose
/// Name of the 2-sigma ellipse of kept landmark `id` in coverage cluster `cluster` (-1: none).
std::string keptLandmark(long long id, int cluster);
}  // namespace scene_names

/// The map as an MRPT 3D scene (what map.png shows, in MRPT's viewer): estimated and ground-truth
/// trajectories, each kept landmark's 2-sigma ellipse (CEllipsoid2D, quantile 2) and centre
/// coloured by its coverage cluster (map.png's palette), dropped landmarks as red crosses, ground
/// truth landmarks as grey points, the robot (MRPT's Pioneer model) at `robot`, a grid and the
/// title. Units: metres, z = 0 plane; the camera looks at the map from above at 45 degrees.
mrpt::opengl::COpenGLScene::Ptr buildMapScene(const MapContent& content, const Pose2& robot);

/// Writes buildMapScene() to `path` (MRPT's gzip-compressed .3Dscene, COpenGLScene::saveToFile,
/// opened by SceneViewer3D) through a temporary file and a rename, so a reader never sees half a
/// scene. Throws Error if it cannot write.
void writeMapScene(const std::string& path, const MapContent& content, const Pose2& robot);

}  // namespace budget_slam::report
