"""The team agent's shared parts: the team message sent over the radio, and its decoding."""
