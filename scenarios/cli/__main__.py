"""``python -m scenarios.cli``: the ``robotstadium`` command."""

from scenarios.launch import main

raise SystemExit(main())
