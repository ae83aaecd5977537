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
