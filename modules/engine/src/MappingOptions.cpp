#include "budget_slam/engine/MappingOptions.h"

#include "budget_slam/core/Error.h"
#include "budget_slam/engine/BuiltinBackends.h"

namespace budget_slam::runs {
namespace {

using O = MappingOptions;

OptionKey<O> backendKey() {
  return {"backend",
          [](O& o, const IniSection& s) {
            o.backend = s.readChoice("backend", o.backend, MappingOptions::backends());
          },
          [](const O& o) { return o.backend; }, "a backend's registry name"};
}

/// kf-slam's SAVE_3D_SCENES and SAVE_LOG_FREQUENCY make one field. kf-slam's default
/// SAVE_3D_SCENES = true would write a scene a step of a lifelong run, so budget-slam writes them
/// only when the ini asks; SAVE_LOG_FREQUENCY is read (and checked) only then.
OptionKey<O> scenesKey() {
  return {"SAVE_3D_SCENES",
          [](O& o, const IniSection& s) {
            o.scene_every_steps =
                s.readBool("SAVE_3D_SCENES", false)
                    ? static_cast<std::size_t>(s.readInt("SAVE_LOG_FREQUENCY", 1, 1))
                    : 0;
          },
          [](const O& o) { return std::string(o.scene_every_steps ? "true" : "false"); }, ""};
}

OptionKey<O> sceneFrequencyKey() {
  return {"SAVE_LOG_FREQUENCY", [](O&, const IniSection&) {},  // read with SAVE_3D_SCENES
          [](const O& o) { return std::to_string(o.scene_every_steps ? o.scene_every_steps : 1); },
          "[steps]"};
}

/// kf-slam's default is the 3D filter, but an ini that does not say is taken as 2D here.
OptionKey<O> filterKey() {
  return {"kf_implementation",
          [](O& o, const IniSection& s) {
            o.kf_implementation = s.readChoice("kf_implementation", o.kf_implementation,
                                               {"CRangeBearingKFSLAM2D", "CRangeBearingKFSLAM"});
            if (o.kf_implementation != "CRangeBearingKFSLAM2D")
              throw KeyError(s.name(), "kf_implementation",
                             "[" + s.name() + "] kf_implementation = " + o.kf_implementation +
                                 ": budget-slam runs the 2D filter, CRangeBearingKFSLAM2D");
          },
          [](const O& o) { return o.kf_implementation; }, ""};
}

}  // namespace

const std::vector<std::string>& MappingOptions::backends() {
  static const std::vector<std::string> b = builtinBackends().names();
  return b;
}

const OptionTable<MappingOptions>& MappingOptions::table() {
  static const OptionTable<O> t = {
      option::text("rawlog_file", &O::rawlog_file),
      backendKey(),
      option::text("ground_truth_file", &O::ground_truth_file, "empty = next to the rawlog"),
      option::text("ground_truth_file_robot", &O::ground_truth_file_robot,
                   "empty = next to the rawlog"),
      option::text("logOutput_dir", &O::logOutput_dir),
      option::integer("max_steps", &O::max_steps, 0, std::numeric_limits<long long>::max(),
                      "[steps], 0 = the whole rawlog"),
      option::flag("keep_history", &O::keep_history),
      option::flag("save_3d_scene", &O::save_3d_scene),
      scenesKey(),
      sceneFrequencyKey(),
      filterKey(),
  };
  return t;
}

}  // namespace budget_slam::runs
