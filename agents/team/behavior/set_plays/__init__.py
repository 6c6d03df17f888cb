"""Set plays: the game situations that ask for more than open play (throw-ins, kick-offs, a ball going out,
a ball at the own goal line beside the goal)."""
