"""pytest settings of the Python package's tests: the `slow` marker of the slow tier
(scripts/test-slow.sh runs `-m slow`, scripts/test.sh `-m "not slow"`)."""


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: slow tier (scripts/test-slow.sh), needs ROSS")
