import os

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "stickslip",
    deadline=None,
    max_examples=int(os.environ.get("STICKSLIP_HYPOTHESIS_EXAMPLES", "40")),
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=True,
)
settings.load_profile("stickslip")

# the law registered by the tests only (tests/laws_for_tests.py): every conformance test runs on it
import laws_for_tests  # noqa: E402, F401


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Refuse a test marked both fast and slow: ``-m fast`` replaces the default ``-m 'not slow'``
    (the last -m given wins), so such a test would put a slow test in the fast tier."""
    both = [i.nodeid for i in items if i.get_closest_marker("fast") and i.get_closest_marker("slow")]
    if both:
        raise pytest.UsageError("marked both fast and slow: " + ", ".join(both))
