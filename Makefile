# Two commands: `make demo` and `make test`. Both set everything up first.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

# apt-get as root, else through sudo (never prompting: CI has no terminal).
SUDO   := $(shell [ "$$(id -u)" = 0 ] || echo "sudo -n")

.PHONY: setup browser demo test lint typecheck contracts pytest pytest-nojit bench clean

setup: $(STAMP) browser

# Debian's chromium for the browser test (Playwright drives it; no browser download).
browser:
	@command -v chromium >/dev/null 2>&1 || { \
	  echo "Installing Debian's chromium for the browser test"; \
	  $(SUDO) apt-get update -qq && \
	  $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; \
	} || echo "warning: could not install chromium: the browser test will be skipped (it fails under CI)"

# Reinstall only when the package definition changes: `make setup` is quick otherwise.
$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev]'
	@echo "Compiling the default run's kernels (tumble warm-up)"
	$(BIN)/tumble warm-up --quiet
	@touch $(STAMP)

# The main job: the built-in gyroscope scenario; it prints where its report is.
demo: setup
	$(BIN)/tumble run

lint: setup
	$(BIN)/ruff check src tests bench examples

typecheck: setup
	$(BIN)/mypy

contracts: setup
	$(BIN)/lint-imports

pytest: setup
	$(BIN)/pytest -q

# The compiled core once more as plain Python, so coverage and tracebacks see the kernels.
pytest-nojit: setup
	NUMBA_DISABLE_JIT=1 $(BIN)/pytest -q tests/core
	NUMBA_DISABLE_JIT=1 $(BIN)/pytest -q tests/test_sweep.py -k "quarter or symmetric or single_body or nutation"

test: lint typecheck contracts pytest pytest-nojit

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
	$(BIN)/python bench/refusals.py

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache .hypothesis
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
