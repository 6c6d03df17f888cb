"""The physical world of a match: field, robots, ball, cameras and sensors (no rules, no agents)."""
