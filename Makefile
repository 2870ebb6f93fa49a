# Two set-up commands for a fresh machine with only Python and pip: `make demo`, `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.impedax-installed
# test processes (pytest-xdist; each test file runs whole in one of them): 2 uses both cores of
# the CI machine; each process holds its own JAX (~2.5 GB at most), so keep it small
PYTEST_WORKERS ?= 2

.PHONY: demo test test-all bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e ".[test,draw,formats]"
	touch $(STAMP)

# impedax's bytecode (__pycache__), brought up to date before each run: where
# PYTHONDONTWRITEBYTECODE is set, no process writes it, and each `impedax` process (the tests
# start hundreds) would compile impedax's modules from source, 0.2-0.4 s apiece
BYTECODE := $(BIN)/python -m compileall -q impedax

demo: $(STAMP)
	$(BYTECODE)
	$(BIN)/impedax demo $(DEMO_ARGS)

test: $(STAMP)
	$(BYTECODE)
	$(BIN)/python -m pytest -n $(PYTEST_WORKERS) --dist loadfile $(PYTEST_ARGS)

test-all: $(STAMP)
	$(BYTECODE)
	$(BIN)/python -m pytest -n $(PYTEST_WORKERS) --dist loadfile -m "" $(PYTEST_ARGS)

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e ".[bench,dask]"
	$(BIN)/python benchmarks/run_all.py

clean:
	rm -rf $(VENV) out .pytest_cache
