# `make demo` installs tumble with its runtime dependencies only and runs the
# built-in scenario; `make check` is the quick loop while editing; `make test`
# (what CI runs) is every check; `make docs` builds the site. Those three set up
# everything the checks need first: the dev, docs, robots, robot-files and
# engines extras, and Debian's chromium for the browser test.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
RUNTIME := $(VENV)/.runtime
STAMP  := $(VENV)/.installed

# The tests run in one pytest-xdist worker per core (JOBS=1 for one process, to
# use a debugger), a file at a time: the tests of a file share compiled kernels,
# and two workers would each compile those they reach at the same moment.
JOBS   ?= $(shell nproc 2>/dev/null || echo 2)
XDIST  := $(if $(filter 1,$(JOBS)),-p no:xdist,-n $(JOBS) --dist loadfile)
# Without the JIT nothing is compiled: the tests go to the workers one by one.
NOJIT  := NUMBA_DISABLE_JIT=1 $(BIN)/pytest -q $(if $(filter 1,$(JOBS)),-p no:xdist,-n $(JOBS))

# apt-get as root, else through sudo (never prompting: CI has no terminal).
SUDO   := $(shell [ "$$(id -u)" = 0 ] || echo "sudo -n")

.PHONY: setup browser demo docs doctest check test lint typecheck contracts pytest pytest-fast \
	pytest-site pytest-nojit bench clean

setup: $(STAMP) browser

# Debian's chromium for the browser test (Playwright drives it; no browser download).
browser:
	@command -v chromium >/dev/null 2>&1 || { \
	  echo "Installing Debian's chromium for the browser test"; \
	  $(SUDO) apt-get update -qq && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; \
	} || echo "warning: could not install chromium: the browser test will be skipped (it fails under CI)"

# Reinstall only when the package definition changes: set-up is quick otherwise.
# tumble and what it needs to run, nothing else, and the default run's kernels
# compiled (tumble warm-up).
$(RUNTIME): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e .
	@echo "Compiling the default run's kernels (tumble warm-up)"
	$(BIN)/tumble warm-up --quiet
	@touch $(RUNTIME)

# Everything the checks, the site and the tests of real files need besides.
$(STAMP): $(RUNTIME)
	$(BIN)/python -m pip install --quiet -e '.[dev,docs,robots,robot-files,engines]'
	@touch $(STAMP)

# The main job: the built-in gyroscope scenario; it prints where its report is.
demo: $(RUNTIME)
	$(BIN)/tumble run

# The documentation site, from the sources in docs/: every tutorial, guide and
# example executed, every warning an error (-W), every reference resolved (-n).
docs: setup
	MPLBACKEND=Agg $(BIN)/sphinx-build -b html -n -W --keep-going -q docs docs/_build/html
	@echo "The site: docs/_build/html/index.html"

# The Examples sections of the docstrings, run.
doctest: setup
	$(BIN)/pytest -q --doctest-modules src/tumble

lint: setup
	$(BIN)/ruff check src tests bench examples docs

typecheck: setup
	$(BIN)/mypy

contracts: setup
	$(BIN)/lint-imports

# The whole suite but the tests of the built site (pytest-site), which need make docs.
pytest: setup
	$(BIN)/pytest -q $(XDIST) -m "not site"

# The tests of the site (links, the browser, the reference): they read docs/_build/html.
pytest-site: docs
	$(BIN)/pytest -q -m site

# The compiled core once more as plain Python, so coverage and tracebacks see the
# kernels: each sweep kernel's every line through the chunk tests (their metrics
# against simulate's histories), the closed-form oracles with the exact solution.
# The oracles of the stepped methods run compiled in pytest (as plain Python,
# thousands of steps of nine bodies take a minute each).
pytest-nojit: setup
	$(NOJIT) tests/core
	$(NOJIT) tests/test_sweep.py -k "symmetric or single_body or (quarter and exact) or (nutation and exact)"

# The suite less the slow tests (kills, long fuzzing, large sweeps of kernel
# variants) and the site's: for the loop of editing.
pytest-fast: setup
	$(BIN)/pytest -q $(XDIST) -m "not slow and not site"

# While editing: lint, types, contracts and the fast tests (about 4 minutes once
# numba's cache is filled; the first run compiles the kernels).
check: setup
	@$(MAKE) --no-print-directory lint typecheck contracts pytest-fast

# Every check. The site and the tests run side by side (the site's tests after
# it), so that both cores stay busy.
test: setup
	@$(MAKE) --no-print-directory -j3 docs pytest lint typecheck contracts doctest \
	  pytest-nojit pytest-site

bench: setup
	$(BIN)/python -m pip install --quiet -e '.[dev,bench]'
	$(BIN)/python bench/mass_properties.py --repairs
	$(BIN)/python bench/real_meshes.py
	$(BIN)/python bench/free_body.py
	$(BIN)/python bench/heavy_top.py
	$(BIN)/python bench/lagrange_top.py
	$(BIN)/python bench/exact_splitting.py
	$(BIN)/python bench/batch.py
	$(BIN)/python bench/sweep.py
	$(BIN)/python bench/accuracy.py
	$(BIN)/python bench/end_to_end.py
	$(BIN)/python bench/spacecraft.py
	$(BIN)/python bench/cold_call.py
	$(BIN)/python bench/refusals.py
	$(BIN)/python bench/hostile.py
	$(BIN)/python bench/identify.py
	@test -f bench/.venv-ross/.installed || { $(PYTHON) -m venv bench/.venv-ross && \
	  bench/.venv-ross/bin/pip install --quiet -r bench/requirements-ross.txt && \
	  touch bench/.venv-ross/.installed; }
	$(BIN)/python bench/rotors.py
	$(BIN)/python bench/run_up.py

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache .hypothesis
	rm -rf docs/_build docs/auto_tutorials docs/auto_how-to docs/auto_examples docs/reference/generated
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
