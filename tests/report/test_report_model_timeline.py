"""The planner's model timeline: one bar per pair, segments by the model in force."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from poissonkit.report.nbody_plots import model_timeline_axes  # noqa: E402

PLAN = {"pairs": [{"bodies": ["a", "b"], "model": "dipole"},
                  {"bodies": ["a", "c"], "model": "cylinder"}]}


def _bars(ax):
    return [(round(p.get_x(), 12), round(p.get_width(), 12)) for p in ax.patches
            if p.get_width() > 0]


def test_initial_plan_only_is_one_segment_per_pair_over_the_run():
    ax = model_timeline_axes(PLAN, 2.0)
    assert _bars(ax) == [(0.0, 2.0), (0.0, 2.0)]
    assert [t.get_text() for t in ax.get_yticklabels()] == ["a-b", "a-c"]
    assert "initial plan" in ax.get_title()
    assert sorted(t.get_text() for t in ax.get_legend().get_texts()) == ["cylinder", "dipole"]
    plt.close("all")


def test_switches_split_the_bar_of_their_pair():
    plan = {"initial_plan": PLAN, "switches": [
        {"t_s": 0.5, "bodies": ["a", "b"], "from": "dipole", "to": "dumbbell"}]}
    ax = model_timeline_axes(plan, 2.0)
    assert _bars(ax) == [(0.0, 0.5), (0.5, 1.5), (0.0, 2.0)]
    assert "initial plan" not in ax.get_title()
    plt.close("all")
