"""Everything around the simulator that is run from the command line.

- :mod:`scenarios.cli`: the ``robotstadium`` command, one module per subcommand;
- :mod:`scenarios.common`: file writers, figures, statistics and the batch engine, which several
  concerns use;
- :mod:`scenarios.tools`: the world demo, the benchmark, the colour calibration;
- :mod:`scenarios.perception`: vision percepts scored against ground truth;
- :mod:`scenarios.localization`: thesis chapter 6's scenarios, batch runs, statistics and plots
  (the built-in scenario files ``scenario_1.toml`` .. ``scenario_3.toml`` are data of this package);
- :mod:`scenarios.matches`: full matches with the built-in policies;
- :mod:`scenarios.tournament`: many matches between policies, their statistics and verdicts.

The concerns import :mod:`scenarios.common` but not each other; only the command line puts
them together (import-linter contracts in pyproject.toml).
"""

import world  # noqa: F401,E402 - first: it caps numpy's SIMD kernels before numpy is imported
