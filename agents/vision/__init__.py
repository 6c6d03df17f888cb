"""Landmark recognition (thesis chapter 4): from one camera frame to landmark percepts."""
