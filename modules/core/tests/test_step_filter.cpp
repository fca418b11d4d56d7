#include <gtest/gtest.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include "budget_slam/core/StepFilter.h"

using namespace budget_slam;

namespace {
Step makeStep() {
  auto obs = std::make_shared<mrpt::obs::CObservationBearingRange>();
  for (int id : {3, 7, -1, 9}) {
    mrpt::obs::CObservationBearingRange::TMeasurement m;
    m.range = 1.0 + id;
    m.yaw = 0.1;
    m.pitch = 0;
    m.landmarkID = id;
    obs->sensedData.push_back(m);
  }
  Step s;
  s.frame = std::make_shared<mrpt::obs::CSensoryFrame>();
  s.frame->insert(obs);
  RangeBearingScan scan;
  for (const auto& m : obs->sensedData)
    scan.readings.push_back({m.landmarkID < 0 ? kNoLandmarkId : m.landmarkID, m.range, m.yaw, 0});
  s.scan = scan;
  return s;
}
}  // namespace

TEST(StepFilter, RemovesReadingsOfGivenIdsFromTheScanAndSharesTheRawlogObjects) {
  const Step s = makeStep();
  const Step f = withoutReadingsOf(s, {7, 9});
  ASSERT_EQ(f.scan->readings.size(), 2u);
  EXPECT_EQ(f.scan->readings[0].id, 3);
  EXPECT_EQ(f.scan->readings[1].id, kNoLandmarkId);
  // The rawlog's frame is shared and untouched; the original scan too.
  EXPECT_EQ(f.frame, s.frame);
  EXPECT_EQ(
      s.frame->getObservationByClass<mrpt::obs::CObservationBearingRange>()->sensedData.size(), 4u);
  EXPECT_EQ(s.scan->readings.size(), 4u);
}

TEST(StepFilter, SharesObjectsWhenNothingIsFiltered) {
  const Step s = makeStep();
  const Step f = withoutReadingsOf(s, {100});
  EXPECT_EQ(f.frame, s.frame);
  EXPECT_EQ(f.scan->readings.size(), 4u);
}
