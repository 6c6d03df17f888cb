"""The team agent's modelling: providers that turn each step's observation into representations.

Each provider (one module) produces one representation, a frozen value with units and frame in its
field names, from the observation and the representations before it; :class:`WorldModeller`
runs them in order, once per step, and bundles what they produced in a :class:`WorldModel`
snapshot, which is all the behaviour (:mod:`agents.team.behavior`) reads.
"""
