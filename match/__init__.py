"""The rules of a match and its interface: protocol, referee, radio, env and runner."""
