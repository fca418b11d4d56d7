#include <algorithm>
#include <cmath>

#include "Random.h"
#include "Scenario.h"
#include "budget_slam/core/Error.h"

namespace budget_slam::dataset::sim {
namespace {

using V = Eigen::Vector2d;
constexpr double kDeg = M_PI / 180;

/// `n` landmarks uniform in [lo, hi], at least `spacing` apart (rejection sampling), ids from
/// `next_id`, visible from `region` only (-1: anywhere).
void scatter(Scenario& s, Random& rng, int n, V lo, V hi, int region, double spacing,
             LandmarkId& next_id, int first_lap = 0) {
  for (int placed = 0, tries = 0; placed < n && tries < 1000 * n; ++tries) {
    const V p = quantize(V(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y())));
    const bool crowded =
        spacing > 0 &&
        std::any_of(s.world.landmarks.begin(), s.world.landmarks.end(), [&](const Landmark& l) {
          return l.last_lap >= first_lap && (l.p - p).norm() < spacing;
        });
    if (crowded) continue;
    Landmark l;
    l.id = next_id++;
    l.p = p;
    l.region = region;
    l.first_lap = first_lap;
    s.world.landmarks.push_back(l);
    ++placed;
  }
}

/// A wall from a to b with door gaps [d - w/2, d + w/2] along it (d: distances from a).
void wallWithDoors(World& w, V a, V b, std::vector<double> doors, double width) {
  const double len = (b - a).norm();
  const V dir = (b - a) / len;
  std::sort(doors.begin(), doors.end());
  double from = 0;
  for (const double d : doors) {
    if (d - width / 2 > from) w.walls.push_back({a + from * dir, a + (d - width / 2) * dir});
    from = d + width / 2;
  }
  if (from < len) w.walls.push_back({a + from * dir, b});
}

/// Walls around an axis-aligned box; `doors` on its top (+y) or bottom (-y) side at given x.
void box(World& w, V lo, V hi, std::vector<double> top_doors_x, std::vector<double> bottom_doors_x,
         double door) {
  for (auto& x : top_doors_x) x -= lo.x();
  for (auto& x : bottom_doors_x) x -= lo.x();
  wallWithDoors(w, V(lo.x(), lo.y()), V(hi.x(), lo.y()), bottom_doors_x, door);
  wallWithDoors(w, V(lo.x(), hi.y()), V(hi.x(), hi.y()), top_doors_x, door);
  w.walls.push_back({V(lo.x(), lo.y()), V(lo.x(), hi.y())});
  w.walls.push_back({V(hi.x(), lo.y()), V(hi.x(), hi.y())});
}

// Choudhary et al.'s synthetic set: 50 x 50 m, 23 landmarks, 96 poses, about 420 measurements,
// no loop closure. A lawnmower drive with a 360 deg, 14.5 m sensor gives about those numbers.
Scenario paperSynthetic(Random& rng) {
  Scenario s;
  s.name = "paper-synthetic";
  s.description =
      "Like Choudhary et al.'s synthetic set: 50 x 50 m, 23 landmarks, lawnmower drive without "
      "loop closure.";
  LandmarkId id = 1;
  scatter(s, rng, 23, V(2, 2), V(48, 48), -1, 4.0, id);
  s.start = V(5, 6);
  s.route = {V(45, 6), V(45, 25), V(5, 25), V(5, 44), V(43, 44)};
  s.step = 1.75;
  s.max_turn = 45 * kDeg;
  s.sensor.min_range = 0.5;  // closer, the bearing Jacobian (1/r) blows an EKF up
  s.sensor.max_range = 14.5;
  s.sensor.fov_yaw = 2 * M_PI;
  s.sensor.std_range = 0.1;
  s.sensor.std_yaw = 1 * kDeg;
  s.odo_std_xy = 0.05;
  s.odo_std_yaw = 0.5 * kDeg;
  return s;
}

// Hochdorfer & Schlegel's experiment: a lab dense with landmarks, the hallway, a second room
// (C12) with few; 0.3 m steps; loops of about 8 m and 14 m in the lab and 10 m through its two
// doors; landmarks seen only from inside their room.
Scenario rooms(Random& rng) {
  Scenario s;
  s.name = "rooms";
  s.description =
      "Like Hochdorfer & Schlegel's experiment: lab (115 landmarks), hallway (25), room C12 "
      "(15), seen only from inside their room; 0.3 m steps; loops of 8, 10 and 14 m.";
  auto& w = s.world;
  w.regions = {
      {"lab", V(0, 0), V(10, 8)}, {"hallway", V(0, 8), V(26, 10.5)}, {"C12", V(16, 0), V(26, 8)}};
  box(w, V(0, 0), V(10, 8), {3, 6.5}, {}, 1.0);  // lab: doors A (x = 3) and B (x = 6.5)
  box(w, V(16, 0), V(26, 8), {20}, {}, 1.0);     // C12: door at x = 20
  w.walls.push_back({V(0, 10.5), V(26, 10.5)});  // hallway: far wall, ends, the part between
  w.walls.push_back({V(0, 8), V(0, 10.5)});
  w.walls.push_back({V(26, 8), V(26, 10.5)});
  w.walls.push_back({V(10, 8), V(16, 8)});
  LandmarkId id = 1;
  scatter(s, rng, 115, V(0.3, 0.3), V(9.7, 7.7), 0, 0.2, id);
  scatter(s, rng, 25, V(0.3, 8.3), V(25.7, 10.2), 1, 0.2, id);
  scatter(s, rng, 15, V(16.3, 0.3), V(25.7, 7.7), 2, 0.2, id);
  s.start = V(2, 2);
  s.route = {// loop 1 (8 m) in the lab
             V(4.5, 2), V(4.5, 3.5), V(2, 3.5), V(2, 2),
             // loop 2 (about 10 m): out through door A, back in through door B
             V(3, 7), V(3, 9.25), V(6.5, 9.25), V(6.5, 7), V(3, 7), V(3, 9.25),
             // along the hallway into C12 and around it
             V(20, 9.25), V(20, 6), V(24, 6), V(24, 2), V(18, 2), V(18, 6), V(20, 6), V(20, 9.25),
             // back to the lab through door B; loop 3 (14 m) around the meeting table
             V(6.5, 9.25), V(6.5, 5), V(2.5, 5), V(2.5, 2.5), V(7, 2.5), V(7, 5), V(2.5, 5),
             V(2.5, 2.5), V(5, 2.5)};
  // Revisit: from the hallway, westwards into the lab through door B, around its edge, out
  // through door A, along the hallway into C12, around it, and to the hallway's east end.
  s.revisit_start = V(13, 9.25);
  s.revisit_start_yaw = M_PI;
  s.revisit_route = {V(6.5, 9.25), V(6.5, 7),   V(6.5, 5.5),  V(8.5, 5.5),  V(8.5, 1.2),
                     V(1.3, 1.2),  V(1.3, 6.3), V(3, 7),      V(3, 9.25),   V(20, 9.25),
                     V(20, 6),     V(17.3, 6),  V(17.3, 1.5), V(24.7, 1.5), V(24.7, 6.5),
                     V(20, 6.5),   V(20, 9.25), V(25, 9.25)};
  s.step = 0.3;
  s.max_turn = 30 * kDeg;
  s.sensor.min_range = 0.2;
  s.sensor.max_range = 3.0;
  s.sensor.fov_yaw = M_PI;
  s.sensor.sensor_pose_on_robot = mrpt::math::TPose3D(0.1, 0, 0, 0, 0, 0);
  s.sensor.std_range = 0.03;
  s.sensor.std_yaw = 1 * kDeg;
  s.odo_std_xy = 0.01;
  s.odo_std_yaw = 0.5 * kDeg;
  return s;
}

// Victoria-Park-like: about 150 trees over 200 x 250 m, a long drive with several loops, a
// 180 deg laser that sees trees out to 25 m.
Scenario park(Random& rng) {
  Scenario s;
  s.name = "park";
  s.description =
      "Victoria-Park-like: 150 trees over 200 x 250 m, a 2 km drive with several loops, 180 deg "
      "laser to 25 m.";
  LandmarkId id = 1;
  scatter(s, rng, 150, V(5, 5), V(195, 245), -1, 6.0, id);
  s.start = V(20, 20);
  s.route = {V(180, 20),  V(180, 230), V(20, 230), V(20, 20),   // the perimeter
             V(20, 125),  V(180, 125), V(180, 20), V(100, 20),  // southern loop
             V(100, 230), V(20, 230),  V(20, 125), V(100, 125), V(100, 60), V(60, 60)};
  // Revisit: a lawnmower from the north-west, rows 40-50 m apart across the whole park.
  s.revisit_start = V(40, 200);
  s.revisit_start_yaw = 0;
  s.revisit_route = {V(160, 200), V(160, 160), V(40, 160), V(40, 110), V(160, 110),
                     V(160, 60),  V(40, 60),   V(40, 30),  V(190, 30)};
  s.step = 1.0;
  s.max_turn = 20 * kDeg;
  s.sensor.min_range = 1.0;
  s.sensor.max_range = 25;
  s.sensor.fov_yaw = M_PI;
  s.sensor.std_range = 0.15;
  s.sensor.std_yaw = 1 * kDeg;
  s.odo_std_xy = 0.03;
  // MRPT's 2D EKF (kf-slam) diverges to NaN on this 1.8 km drive with 0.2 deg or more of yaw
  // noise per step (cause not found; with 0.1 deg it is stable). docs/DATASETS.md.
  s.odo_std_yaw = 0.1 * kDeg;
  return s;
}

// A large building for runs of 100,000 steps and more: a 120 m corridor with 12 rooms on each
// side (80 landmarks a room, 150 in the corridor), walls with doors that occlude. Each lap visits
// every room; between laps a tenth of the landmarks disappears and as many new ones appear.
Scenario lifelong(Random& rng, int laps) {
  Scenario s;
  s.name = "lifelong";
  s.laps = std::max(1, laps);
  s.change_fraction = 0.1;
  s.description = "Lifelong: 120 m corridor, 24 rooms, about 2,000 landmarks, " +
                  std::to_string(s.laps) +
                  " laps; between laps 10% of the landmarks disappear and as many appear.";
  auto& w = s.world;
  std::vector<double> bottom_doors, top_doors;
  for (int i = 0; i < 12; ++i) {
    const double cx = 10.0 * i + 5;
    box(w, V(cx - 5, 0), V(cx + 5, 10), {cx}, {}, 1.2);
    box(w, V(cx - 5, 13), V(cx + 5, 23), {}, {cx}, 1.2);
  }
  w.walls.push_back({V(0, 10), V(0, 13)});
  w.walls.push_back({V(120, 10), V(120, 13)});
  // Landmarks of a room or the corridor, placed for lap `lap`.
  std::vector<std::pair<V, V>> areas = {{V(0.3, 10.3), V(119.7, 12.7)}};
  for (int i = 0; i < 12; ++i) {
    const double cx = 10.0 * i + 5;
    areas.push_back({V(cx - 4.7, 0.3), V(cx + 4.7, 9.7)});
    areas.push_back({V(cx - 4.7, 13.3), V(cx + 4.7, 22.7)});
  }
  LandmarkId id = 1;
  scatter(s, rng, 150, areas[0].first, areas[0].second, -1, 0.3, id);
  for (std::size_t a = 1; a < areas.size(); ++a)
    scatter(s, rng, 80, areas[a].first, areas[a].second, -1, 0.3, id);
  // The changing world: before lap L, a fraction of the landmarks alive in lap L-1 goes, and as
  // many new ones appear in random rooms (new ids, never reused).
  for (int lap = 1; lap < s.laps; ++lap) {
    std::vector<std::size_t> alive;
    for (std::size_t i = 0; i < w.landmarks.size(); ++i)
      if (w.landmarks[i].first_lap <= lap - 1 && w.landmarks[i].last_lap >= lap - 1)
        alive.push_back(i);
    const auto n = static_cast<std::size_t>(std::lround(s.change_fraction * alive.size()));
    for (std::size_t k = 0; k < n; ++k) {  // partial Fisher-Yates: n distinct victims
      const std::size_t j = k + static_cast<std::size_t>(rng.uniform() * (alive.size() - k));
      std::swap(alive[k], alive[j]);
      w.landmarks[alive[k]].last_lap = lap - 1;
    }
    for (std::size_t k = 0; k < n; ++k) {
      const auto& area = areas[static_cast<std::size_t>(rng.uniform() * areas.size())];
      scatter(s, rng, 1, area.first, area.second, -1, 0.3, id, lap);
    }
  }
  s.start = V(1, 11.5);
  // One lap: east along the corridor visiting the rooms below, west visiting the rooms above.
  for (int i = 0; i < 12; ++i) {
    const double cx = 10.0 * i + 5;
    for (const V& p :
         {V(cx, 11.5), V(cx, 8.5), V(cx + 3, 6), V(cx, 2.5), V(cx - 3, 6), V(cx, 8.5), V(cx, 11.5)})
      s.route.push_back(p);
  }
  for (int i = 11; i >= 0; --i) {
    const double cx = 10.0 * i + 5;
    for (const V& p : {V(cx, 11.5), V(cx, 14.5), V(cx - 3, 17), V(cx, 20.5), V(cx + 3, 17),
                       V(cx, 14.5), V(cx, 11.5)})
      s.route.push_back(p);
  }
  s.route.push_back(V(1, 11.5));
  s.step = 0.5;
  s.max_turn = 30 * kDeg;
  s.sensor.min_range = 0.2;
  s.sensor.max_range = 5;
  s.sensor.fov_yaw = M_PI;
  s.sensor.std_range = 0.05;
  s.sensor.std_yaw = 1 * kDeg;
  s.odo_std_xy = 0.01;
  s.odo_std_yaw = 0.5 * kDeg;
  return s;
}

// An office floor of long corridors with few landmarks: a 60 x 40 m building, corridors 2.4 m
// wide along its four sides and through its middle both ways, solid blocks between them (walls
// occlude), landmarks on the corridor walls 2 to 8 m apart (about 120), a 180 deg sensor to 8 m.
// Few landmarks are in view at a time and each corridor is long: a tight cap must keep some in
// every stretch of every corridor.
Scenario corridors(Random& rng) {
  Scenario s;
  s.name = "corridors";
  s.description =
      "Office floor: 60 x 40 m, corridors 2.4 m wide around and through the middle both ways, "
      "landmarks on the corridor walls 2-8 m apart, 180 deg sensor to 8 m.";
  auto& w = s.world;
  const double W = 60, H = 40, c = 2.4;                 // building, corridor width [m]
  const double xm = W / 2 - c / 2, ym = H / 2 - c / 2;  // the middle corridors' low sides
  w.walls.push_back({V(0, 0), V(W, 0)});
  w.walls.push_back({V(W, 0), V(W, H)});
  w.walls.push_back({V(W, H), V(0, H)});
  w.walls.push_back({V(0, H), V(0, 0)});
  const std::vector<std::pair<V, V>> blocks = {{V(c, c), V(xm, ym)},
                                               {V(xm + c, c), V(W - c, ym)},
                                               {V(c, ym + c), V(xm, H - c)},
                                               {V(xm + c, ym + c), V(W - c, H - c)}};
  for (const auto& [lo, hi] : blocks) box(w, lo, hi, {}, {}, 0);
  // Landmarks 0.2 m off every wall that faces a corridor, at gaps drawn in [2, 8] m.
  LandmarkId id = 1;
  const auto along = [&](V a, V b, V inward) {
    const double len = (b - a).norm();
    const V dir = (b - a) / len;
    for (double d = rng.uniform(0, 4); d < len; d += rng.uniform(2, 8)) {
      Landmark l;
      l.id = id++;
      l.p = quantize(a + d * dir + 0.2 * inward);
      w.landmarks.push_back(l);
    }
  };
  along(V(0, 0), V(W, 0), V(0, 1));  // the outer walls, facing in
  along(V(W, 0), V(W, H), V(-1, 0));
  along(V(W, H), V(0, H), V(0, -1));
  along(V(0, H), V(0, 0), V(1, 0));
  for (const auto& [lo, hi] : blocks) {  // the blocks' walls, facing out
    along(V(lo.x(), lo.y()), V(hi.x(), lo.y()), V(0, -1));
    along(V(hi.x(), lo.y()), V(hi.x(), hi.y()), V(1, 0));
    along(V(hi.x(), hi.y()), V(lo.x(), hi.y()), V(0, 1));
    along(V(lo.x(), hi.y()), V(lo.x(), lo.y()), V(-1, 0));
  }
  const double h = c / 2, xc = W / 2, yc = H / 2;  // corridor centre lines
  s.start = V(h, h);
  // The outer corridors anticlockwise, then the middle one northwards, back to the crossing,
  // and the middle one westwards and eastwards.
  s.route = {V(W - h, h),  V(W - h, H - h), V(h, H - h), V(h, h),     V(xc, h),
             V(xc, H - h), V(xc, yc),       V(h, yc),    V(W - h, yc)};
  // Revisit: from the east side's middle, the outer corridors clockwise, the middle westwards,
  // then the middle north-south.
  s.revisit_start = V(W - h, yc);
  s.revisit_start_yaw = M_PI / 2;
  s.revisit_route = {V(W - h, H - h), V(h, H - h), V(h, h),      V(W - h, h), V(W - h, yc),
                     V(h, yc),        V(xc, yc),   V(xc, H - h), V(xc, h)};
  s.step = 0.4;
  s.max_turn = 30 * kDeg;
  s.sensor.min_range = 0.2;
  s.sensor.max_range = 8.0;
  s.sensor.fov_yaw = M_PI;
  s.sensor.std_range = 0.03;
  s.sensor.std_yaw = 1 * kDeg;
  s.odo_std_xy = 0.01;
  s.odo_std_yaw = 0.3 * kDeg;
  return s;
}

// A large outdoor area with trees in clusters, like Victoria Park's: 240 x 240 m, 16 clusters
// on a jittered 4 x 4 grid 60 m apart (6 to 12 trees each, 4 m spread), 24 lone trees, a 180 deg
// laser to 30 m. Between clusters the robot sees little: a map must keep trees of every cluster.
Scenario clusters(Random& rng) {
  Scenario s;
  s.name = "clusters";
  s.description =
      "Trees in clusters, Victoria-Park-like: 240 x 240 m, 16 clusters of 6-12 trees (4 m "
      "spread) and 24 lone trees, 180 deg laser to 30 m.";
  LandmarkId id = 1;
  std::vector<V> centres;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col)
      centres.push_back(
          V(30 + 60 * col + rng.uniform(-12, 12), 30 + 60 * row + rng.uniform(-12, 12)));
  for (const V& centre : centres) {
    const int n = 6 + static_cast<int>(rng.uniform() * 7);  // 6..12
    for (int placed = 0, tries = 0; placed < n && tries < 1000; ++tries) {
      const V p = quantize(centre + V(rng.normal(4.0), rng.normal(4.0)));
      if ((p - centre).norm() > 10) continue;  // a cluster stays clear of the road beside it
      if (std::any_of(s.world.landmarks.begin(), s.world.landmarks.end(),
                      [&](const Landmark& l) { return (l.p - p).norm() < 1.5; }))
        continue;
      Landmark l;
      l.id = id++;
      l.p = p;
      s.world.landmarks.push_back(l);
      ++placed;
    }
  }
  scatter(s, rng, 24, V(5, 5), V(235, 235), -1, 20.0, id);  // lone trees
  // Drive 14 m south of each cluster, row by row (serpentine), then back south past the west
  // column's clusters to the start (a loop closure); revisit 14 m west of each, column by column
  // from the opposite corner.
  const auto at = [&](int row, int col, V offset) { return centres[4 * row + col] + offset; };
  for (int row = 0; row < 4; ++row)
    for (int k = 0; k < 4; ++k) s.route.push_back(at(row, row % 2 ? 3 - k : k, V(0, -14)));
  s.start = s.route.front() - V(20, 0);
  for (int row = 2; row >= 0; --row) s.route.push_back(at(row, 0, V(-14, 0)));
  s.route.push_back(s.start);
  for (int col = 3; col >= 0; --col)
    for (int k = 0; k < 4; ++k) s.revisit_route.push_back(at(col % 2 ? k : 3 - k, col, V(-14, 0)));
  s.revisit_start = s.revisit_route.front() + V(0, 20);
  s.revisit_start_yaw = -M_PI / 2;
  s.step = 1.0;
  s.max_turn = 20 * kDeg;
  s.sensor.min_range = 1.0;
  s.sensor.max_range = 30;
  s.sensor.fov_yaw = M_PI;
  s.sensor.std_range = 0.15;
  s.sensor.std_yaw = 1 * kDeg;
  s.odo_std_xy = 0.03;
  s.odo_std_yaw = 0.1 * kDeg;  // as park: MRPT's EKF is stable on long drives with this
  return s;
}

}  // namespace

Scenario makeScenario(SimulationOptions::ScenarioKind kind, std::uint64_t seed, int laps,
                      SimulationOptions::Route route) {
  using Kind = SimulationOptions::ScenarioKind;
  Random rng(seed);
  Scenario s;
  switch (kind) {
    case Kind::PaperSynthetic:
      s = paperSynthetic(rng);
      break;
    case Kind::Rooms:
      s = rooms(rng);
      break;
    case Kind::Park:
      s = park(rng);
      break;
    case Kind::Lifelong:
      s = lifelong(rng, laps > 0 ? laps : 2);
      break;
    case Kind::Corridors:
      s = corridors(rng);
      break;
    case Kind::Clusters:
      s = clusters(rng);
      break;
  }
  if (laps > 0) s.laps = laps;
  const bool revisit = route == SimulationOptions::Route::Revisit;
  if (revisit && s.revisit_route.empty())
    throw ConfigError("scenario '" + nameOf(SimulationOptions::scenarioNames(), kind) +
                      "' has no revisit route (rooms, park, corridors and clusters have one)");
  // Shift the world so that the robot starts at the origin, where MRPT's filter starts: the
  // ground truth then compares with its estimate directly (start_yaw is 0 in every scenario).
  const V shift = -s.start;
  for (auto& l : s.world.landmarks) l.p = quantize(l.p + shift);
  for (auto& w : s.world.walls) w.a += shift, w.b += shift;
  for (auto& r : s.world.regions) r.lo += shift, r.hi += shift;
  for (auto& p : s.route) p += shift;
  for (auto& p : s.revisit_route) p += shift;
  s.revisit_start += shift;
  s.start = V(0, 0);
  if (revisit) {
    // Same world, same frame; another start and path.
    s.start = s.revisit_start;
    s.start_yaw = s.revisit_start_yaw;
    s.route = s.revisit_route;
  }
  s.world.index(std::max(2.0, s.sensor.max_range));
  return s;
}

}  // namespace budget_slam::dataset::sim
