"""Full matches with the built-in team policies."""
