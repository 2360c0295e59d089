"""Fuzz tests: print how many inputs each target tried and how they ended."""

from __future__ import annotations


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    import fuzzkit

    lines = fuzzkit.summary_lines()
    if lines:
        terminalreporter.section("fuzz counts")
        for line in lines:
            terminalreporter.write_line(line)
