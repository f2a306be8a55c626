"""Test tiers of the Python suite (docs/PERFORMANCE.md, "Test tiers and build time").

The README's test command (`scripts/test.sh`) runs the fast tier, `-m "not slow"`: the read-back
tests that guard the outputs' formats and values. `scripts/test-slow.sh` (run by CI after it)
runs the tests marked `slow`: the comparison with ROSS and the long runs.
"""


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "slow: slow tier (scripts/test-slow.sh): ROSS side by side, long runs",
    )
