"""A reducer in twenty lines of Python (docs/PYTHON.md "A reducer in Python"): keep the landmarks
seen from the most distinct places. budget-slam run --plugin python/plugins/distinct_places.py
--reducer distinct-places ..."""
import math

import budget_slam


class DistinctPlaces:
    """the landmark seen from the fewest distinct places (grid cells of the robot) goes"""

    def __init__(self, place_size):
        self.place_size = place_size  # [m]
        self.places = {}  # landmark id -> the cells the robot saw it from

    def observe(self, seen):  # every step, before its drops
        x, y, _ = seen.robot
        cell = (math.floor(x / self.place_size), math.floor(y / self.place_size))
        for i in seen.observed.tolist():
            self.places.setdefault(i, set()).add(cell)

    def forget(self, id):  # the landmark left the map
        self.places.pop(id, None)

    def choose(self, drop):  # one score a candidate: the fewest places goes, ties the lowest id
        return [len(self.places.get(i, ())) for i in drop.candidates["id"].tolist()]


budget_slam.register_reducer("distinct-places", DistinctPlaces, options={
    "place_size": (2.0, 0.01, 1000.0, "side of a place's grid cell [m]")})
