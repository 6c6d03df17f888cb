"""Behaviours: what a robot does with what it sees and believes."""
