"""``python -m scenarios.cli``: the ``robotstadium`` command."""

from scenarios.cli import main

raise SystemExit(main())
