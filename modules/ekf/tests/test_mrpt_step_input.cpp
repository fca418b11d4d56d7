// ekf::mrptStepInput: what MRPT's filter is given for a step whose parsed scan lost readings
// (core/StepFilter.h) — the rawlog's observation restricted to the readings kept.
#include <gtest/gtest.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>

#include "budget_slam/core/StepFilter.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/ekf/MrptStepInput.h"

using namespace budget_slam;
using mrpt::obs::CObservationBearingRange;

namespace {

/// A frame with an odometry observation before and after one bearing-range observation of
/// landmarks 3, 7, (no id), 9; and the step parsed from it.
Step makeStep() {
  auto obs = std::make_shared<CObservationBearingRange>();
  obs->validCovariances = true;
  for (int id : {3, 7, -1, 9}) {
    CObservationBearingRange::TMeasurement m;
    m.range = 1.0 + id;
    m.yaw = 0.1 * id;
    m.pitch = 0;
    m.landmarkID = id;
    m.covariance(0, 0) = 0.01 * (id + 2);  // per reading: must travel with its reading
    obs->sensedData.push_back(m);
  }
  auto frame = std::make_shared<mrpt::obs::CSensoryFrame>();
  frame->insert(std::make_shared<mrpt::obs::CObservationOdometry>());
  frame->insert(obs);
  frame->insert(std::make_shared<mrpt::obs::CObservationOdometry>());
  return dataset::parseStep(nullptr, frame, 5, 0.0);
}

const CObservationBearingRange& bearingRangeOf(const mrpt::obs::CSensoryFrame& f) {
  return *f.getObservationByClass<CObservationBearingRange>();
}

}  // namespace

TEST(MrptStepInput, AStepAsParsedSharesTheRawlogsFrame) {
  const Step s = makeStep();
  const auto in = ekf::mrptStepInput(s);
  EXPECT_EQ(in.frame, s.frame);
  ASSERT_TRUE(in.action);  // an empty action for MRPT's filter
  EXPECT_EQ(in.action->size(), 0u);
}

TEST(MrptStepInput, ReadingsLeftOutOfTheScanAreLeftOutOfWhatMrptGets) {
  const Step s = makeStep();
  const Step f = withoutReadingsOf(s, {7, 9});
  const auto in = ekf::mrptStepInput(f);
  ASSERT_NE(in.frame, s.frame);
  ASSERT_EQ(in.frame->size(), 3u);  // the other observations, in their places
  EXPECT_EQ(in.frame->getObservationByIndex(0), s.frame->getObservationByIndex(0));
  EXPECT_EQ(in.frame->getObservationByIndex(2), s.frame->getObservationByIndex(2));
  const auto& kept = bearingRangeOf(*in.frame);
  ASSERT_EQ(kept.sensedData.size(), 2u);
  EXPECT_EQ(kept.sensedData[0].landmarkID, 3);
  EXPECT_EQ(kept.sensedData[1].landmarkID, -1);
  EXPECT_DOUBLE_EQ(kept.sensedData[0].covariance(0, 0), 0.05);
  EXPECT_DOUBLE_EQ(kept.sensedData[1].covariance(0, 0), 0.01);
  EXPECT_TRUE(kept.validCovariances);
  // The rawlog's observation is untouched.
  EXPECT_EQ(bearingRangeOf(*s.frame).sensedData.size(), 4u);
}

TEST(MrptStepInput, AScanThatIsNotTheFramesIsRefused) {
  Step s = makeStep();
  s.scan->readings.pop_back();
  s.scan->readings.back().range += 1;  // no longer a reading of the frame
  EXPECT_THROW(ekf::mrptStepInput(s), std::logic_error);
}

TEST(MrptStepInput, AFrameWithoutBearingRangeGetsAnEmptyOne) {
  Step s;
  s.frame = std::make_shared<mrpt::obs::CSensoryFrame>();
  s.frame->insert(std::make_shared<mrpt::obs::CObservationOdometry>());
  const auto in = ekf::mrptStepInput(s);
  ASSERT_EQ(in.frame->size(), 2u);
  EXPECT_TRUE(bearingRangeOf(*in.frame).sensedData.empty());
  EXPECT_EQ(s.frame->size(), 1u);
}
