#include <gtest/gtest.h>

#include <cmath>

#include "budget_slam/core/PlaceGrid.h"

using namespace budget_slam;

TEST(PlaceGrid, CellsAndHeadingSectorsFromTheSensor) {
  const PlaceGrid g = PlaceGrid::fromSensor(0, 0, 8, M_PI);  // a quarter of 8 m; 720/180 sectors
  EXPECT_DOUBLE_EQ(g.size(), 2.0);
  EXPECT_EQ(g.sectors(), 4u);
  EXPECT_EQ(g.placeOf({-0.1, 4.5, 0.1}), (PlaceKey{-1, 2, 0}));
  EXPECT_EQ(g.placeOf({-0.1, 4.5, -0.1}), (PlaceKey{-1, 2, 3}));  // facing a little right
  EXPECT_EQ(g.placeOf({-0.1, 4.5, M_PI}), (PlaceKey{-1, 2, 2}));
  EXPECT_EQ(g.placeOf({-0.1, 4.5, M_PI}).cell(), (PlaceKey{-1, 2, 0}));
  const PlaceGrid all_round = PlaceGrid::fromSensor(0, 0, 0, 2 * M_PI);  // range unknown: 1 m
  EXPECT_DOUBLE_EQ(all_round.size(), 1.0);
  EXPECT_EQ(all_round.sectors(), 1u);
  const PlaceGrid given = PlaceGrid::fromSensor(0.5, 3, 8, M_PI);
  EXPECT_DOUBLE_EQ(given.size(), 0.5);
  EXPECT_EQ(given.sectors(), 3u);
  EXPECT_THROW(PlaceGrid(0, 1), std::invalid_argument);
  EXPECT_THROW(PlaceGrid(1, 0), std::invalid_argument);
}
