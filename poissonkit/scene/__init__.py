"""Scenes: schema, loader, model-fidelity planner."""
