"""The shipped `oldest` reducer written in Python (docs/PYTHON.md): it makes exactly the built-in
one's decisions (python/tests/test_plugins.py) and measures what a Python reducer costs."""
import budget_slam


class Oldest:
    """the landmark first seen earliest (oldest, in Python)"""

    def choose(self, drop):
        # One score a candidate, its first step: the lowest goes, ties to the lowest id.
        return drop.candidates["first_step"]


budget_slam.register_reducer("py-oldest", Oldest)
