VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: install test match bench perception scenarios docs clean distclean

install: $(STAMP)

# Creates the virtualenv if it is missing; re-installs whenever pyproject.toml changes.
$(STAMP): pyproject.toml Makefile
	test -x $(PY) || python3 -m venv $(VENV)
	$(PY) -m pip install --upgrade pip
	$(PY) -m pip install -e '.[test,ray,browser,learn,docs]'
	$(PY) -m world.compile
	$(PY) -m agents.compile
	touch $@

test: install
	$(PY) -m pytest

match: install
	$(VENV)/bin/robotstadium match --out out/match

bench: install
	$(VENV)/bin/robotstadium bench --out out/bench

perception: install
	$(VENV)/bin/robotstadium perception --frames 1000 --seed 0 --out out/perception

scenarios: install
	$(VENV)/bin/robotstadium scenario all --out out/scenarios

# The documentation site into out/docs (mkdocs.yml); strict: a warning, a broken link or reference fails.
docs: install
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --site-dir out/docs

clean:
	rm -rf out build .pytest_cache .hypothesis .import_linter_cache *.egg-info
	find . -path ./$(VENV) -prune -o -name __pycache__ -type d -exec rm -rf {} +

distclean: clean
	rm -rf $(VENV)
