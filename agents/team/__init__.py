"""The team agent (policy ``team``): modelling as providers into a world model, behaviour as options and
cards, parameters from TOML (:mod:`.agent`, :mod:`.modelling`, :mod:`.behavior`, :mod:`.params`)."""
