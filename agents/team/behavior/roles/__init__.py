"""Roles: the registry (:mod:`.registry`), the assignment over the radio (:mod:`.assignment`), one file per role."""
