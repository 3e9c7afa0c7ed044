# Two commands: `make demo` and `make test`. Both set everything up first.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: setup demo test lint typecheck contracts pytest pytest-nojit bench clean

setup: $(STAMP)

# Reinstall only when the package definition changes: `make setup` is quick otherwise.
$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev]'
	@touch $(STAMP)

demo: setup
	$(BIN)/tumble inertia examples/l_bracket.stl --units mm --density "2700 kg/m^3"
	$(BIN)/tumble inertia solid-cone --mass "250 g" --radius "3 cm" --height "8 cm" --about "0, 0, -2 cm"

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

test: lint typecheck contracts pytest pytest-nojit

bench: setup
	$(BIN)/python -m pip install --quiet -e '.[dev,bench]'
	$(BIN)/python bench/mass_properties.py
	$(BIN)/python bench/free_body.py
	$(BIN)/python bench/batch.py

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache .hypothesis
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
