"""Scenario definitions, batch runs, statistics and plots."""
