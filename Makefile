# Two commands do all the set-up on a fresh machine:
#   make report   -> .venv with certkit, then out/report.pdf, report.html, results.json, tables/
#   make test     -> .venv with certkit and the test tools, then the test suite
#                    (without the checks marked slow; `make test-slow` runs those, CI runs both)
PYTHON ?= python3
VENV   ?= .venv
CAMPAIGN ?= campaigns/seed-amphibian/campaign.yaml
OUT    ?= out

# Python caches compiled modules (and pytest its rewritten test modules) in __pycache__,
# git-ignored: an environment that forbids it (PYTHONDONTWRITEBYTECODE=1) makes every test
# process and every certkit command compile them again
unexport PYTHONDONTWRITEBYTECODE

# constraints.txt pins every package to the versions the tests (and the committed reference
# page images) were made with, so a fresh machine gets the same bytes.  It is made by
# pip-compile from pyproject.toml (`make constraints`), which keeps the pins already in it:
# `make constraints COMPILE_OPTIONS="--upgrade-package NAME"` moves one package
$(VENV)/.installed: pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --disable-pip-version-check -c constraints.txt \
	    -e '.[test]'
	touch $@

.PHONY: install report test test-slow test-postgresql lint docs docs-linkcheck constraints bench bench-catalog clean
install: $(VENV)/.installed

report: $(VENV)/.installed
	$(VENV)/bin/certkit report $(CAMPAIGN) -o $(OUT)

test: $(VENV)/.installed
	$(VENV)/bin/python -m pytest -q -n auto --dist loadfile -m "not slow"

# --durations: the log says which slow checks cost CI's time
test-slow: $(VENV)/.installed
	$(VENV)/bin/python -m pytest -q -n auto --dist loadfile -m slow --durations=15

# the catalog's tests (slow ones too) on SQLite and on a throwaway PostgreSQL server started
# and stopped by .ci/postgresql (Debian's postgresql package; CI runs them within make test
# and make test-slow, with the server .ci/run starts)
test-postgresql: $(VENV)/.installed
	@dir="$$(mktemp -d)"; url="$$(.ci/postgresql start "$$dir" --no-fsync)" || exit 1; \
	CERTKIT_TEST_POSTGRESQL_URL="$$url" $(VENV)/bin/python -m pytest -q -n auto \
	    --dist loadfile tests/test_catalog*.py; \
	status=$$?; .ci/postgresql stop "$$dir"; exit $$status

# ruff from pip, pinned here (its rules are in pyproject.toml); CI runs it
RUFF ?= ruff==0.8.4
lint: $(VENV)/.installed
	$(VENV)/bin/python -m pip install --quiet --disable-pip-version-check "$(RUFF)"
	$(VENV)/bin/ruff check .

# the documentation site (Sphinx, numpydoc, PyData theme; docs/conf.py says why), built with
# warnings as errors; then its examples run (console sessions and doctests) and its links
# are followed (docs/test_examples.py); CI runs it
$(VENV)/.docs-installed: $(VENV)/.installed
	$(VENV)/bin/python -m pip install --quiet --disable-pip-version-check -c constraints.txt \
	    -e '.[test,docs]'
	touch $@

docs: $(VENV)/.docs-installed
	rm -rf docs/_build
	$(VENV)/bin/python -m sphinx -b html -W --keep-going -q docs docs/_build/html
	$(VENV)/bin/python -m pytest -q -p no:cacheprovider --doctest-glob='*.md' docs

# the site's links to other sites: needs the network, which CI's machine has not
docs-linkcheck: $(VENV)/.docs-installed
	$(VENV)/bin/python -m sphinx -b linkcheck -q docs docs/_build/linkcheck

PIP_TOOLS ?= pip-tools==7.6.2
COMPILE_OPTIONS ?=
constraints: pyproject.toml
	$(PYTHON) -m venv .venv-tools
	.venv-tools/bin/python -m pip install --quiet --disable-pip-version-check "$(PIP_TOOLS)"
	.venv-tools/bin/pip-compile --quiet --extra test --extra docs --strip-extras --no-emit-index-url \
	    --no-emit-trusted-host --no-emit-find-links --annotation-style line \
	    $(COMPILE_OPTIONS) --output-file constraints.txt pyproject.toml

bench: $(VENV)/.installed
	$(VENV)/bin/python benchmarks/bench_report.py

# 8 processes x 50 bags added at once, on SQLite and on a throwaway PostgreSQL server
bench-catalog: $(VENV)/.installed
	$(VENV)/bin/python benchmarks/bench_catalog.py

clean:
	rm -rf $(VENV) .venv-tools $(OUT) docs/_build
