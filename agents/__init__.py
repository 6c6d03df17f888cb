"""Team agents that run on the robot and know only what their observations show."""
