import os

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
