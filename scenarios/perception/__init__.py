"""``robotstadium perception``: the vision pipeline's landmark percepts scored against ground truth."""
