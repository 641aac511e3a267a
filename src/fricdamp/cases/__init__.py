"""Analyses that a case file can ask for, each registered in :data:`fricdamp.runner.REGISTRY`."""
