#include "budget_slam/ekf/EkfSlamOptions.h"

namespace budget_slam::ekf {

const EnumNames<EkfSlamOptions::Update>& EkfSlamOptions::updateNames() {
  static const EnumNames<Update> n = {{"sparse", Update::Sparse}, {"mrpt", Update::Mrpt}};
  return n;
}

const OptionTable<EkfSlamOptions>& EkfSlamOptions::table() {
  using O = EkfSlamOptions;
  static const OptionTable<O> t = {
      option::choice("update", &O::update, updateNames(),
                     "sparse (O(n^2) a reading) | mrpt (MRPT's own, O(n^3) a step)"),
  };
  return t;
}

}  // namespace budget_slam::ekf
