"""Found while shipping the planetary scenes: ``wisdom_holman`` with sample times
(``t_eval``, a scene's ``run.save_dt``) an ulp past a multiple of the step stopped at the first
sample time and reported "done" (the circumbinary scene with ``save_dt = 2`` days and
``step = 0.1`` day saved 2 of 1151 states). Its loop ended a piece at ``t0 + n h``, an ulp short
of the piece's end, which the sampler read as a stop by an event; the loop now ends its last
step at the end time itself, as the splittings do. The implicit loop (midpoint, discrete
gradient) had the same end and the same fault: a sampled midpoint run stopped at 0.23 of 11.5
days."""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.numerics.sample_times import uniform_times
from poissonkit.numerics.solver import solve
from poissonkit.scene.build import build_run
from poissonkit.scene.schema import scene_from_mapping

pytestmark = pytest.mark.slow  # a Wisdom–Holman kernel compiles


def _spec():
    return build_run(scene_from_mapping({
        "units": {"length": "AU", "time": "day", "mass": "Msun"},
        "bodies": [{"name": "a", "mass": 0.69, "r": [0.0, 0.0, 0.0]},
                   {"name": "b", "mass": 0.2, "a": 0.224, "e": 0.16},
                   {"name": "p", "mass": 3e-4, "a": 0.705, "e": 0.007, "M": 1.0}],
        "interactions": {"potential": "gravity"},
        "run": {"method": "wisdom_holman", "step": 0.1, "duration": 100.0}}))


@pytest.mark.parametrize("method", ["wisdom_holman", "splitting4", "midpoint"])
def test_sampled_runs_reach_the_end(method):
    spec = _spec()
    # one ulp above 20 steps, as a scene's save_dt = 2 days over step = 0.1 day came out
    times = uniform_times(0.0, float(spec.t_end), np.nextafter(20 * float(spec.step), 1.0))
    sol = solve(spec.system, spec.y0, spec.t_end, method=method, step=spec.step, t_eval=times)
    assert sol.t[-1] == spec.t_end  # the end itself, to the last bit
    assert len(sol.t) == len(times) + 2  # the start, every sample time, the end
    np.testing.assert_array_equal(sol.t[1:-1], times)
    # the same steps as one unsampled run: sampling on the step grid changes no state
    plain = solve(spec.system, spec.y0, spec.t_end, method=method, step=spec.step)
    np.testing.assert_allclose(sol.y[-1], plain.y[-1], rtol=1e-12, atol=1e-15)
