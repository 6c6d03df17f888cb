"""Tournaments: many matches between policies, their statistics with 95% intervals, and a verdict."""
