"""Whole built-in policies besides the team agent: the scripted ball chaser, a robot that stands, and the
move-scan-localize cycle of the thesis' chapter 6 (registered by name in :mod:`agents.policies`)."""
