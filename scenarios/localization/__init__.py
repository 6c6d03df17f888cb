"""Thesis chapter 6: localization scenarios, their runs and batches, statistics, tables and figures."""
