# Two commands for a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed-stamp

.PHONY: run test test-slow docs bench bytecode clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -e ".[test,fast]"
	$(MAKE) --no-print-directory bytecode
	touch $(STAMP)

# The package's bytecode, as a regular (non-editable) install has it: where the environment sets
# PYTHONDONTWRITEBYTECODE, an editable install otherwise compiles every module it imports on
# every start (~0.06 s of CPU for `fingerpad solve`, issue 23). Python recompiles any module
# edited since, in memory.
bytecode:
	$(PY) -m compileall -q src > /dev/null

run: $(STAMP)
	$(VENV)/bin/fingerpad run-default --out out/run

test: $(STAMP)
	$(PY) -m pytest -q -m "not slow"

test-slow: $(STAMP)
	$(PY) -m pytest -q -m slow

# The documentation site (docs/ -> build/docs/index.html): Markdown pages, the API reference from
# the docstrings, the tutorial notebook executed. Warnings are errors, as in tests/test_docs.py.
docs: $(STAMP)
	$(PY) -m sphinx -b html -W --keep-going -q docs build/docs
	@echo "the site: build/docs/index.html"

bench: $(STAMP) bytecode
	$(PY) -m pip install --quiet --disable-pip-version-check -e ".[bench]"
	$(PY) benchmarks/bench_solver.py --grids 1024,2048 --memory 4096
	$(PY) benchmarks/bench_predict.py
	$(PY) benchmarks/bench_population.py
	$(PY) benchmarks/bench_startup.py
	$(PY) benchmarks/bench_sweep.py
	$(PY) benchmarks/bench_population_sweep.py
	$(PY) benchmarks/bench_analyse.py
	$(PY) benchmarks/bench_deflection.py
	test ! -f benchmarks/bench_explorer.py || $(PY) benchmarks/bench_explorer.py
	$(PY) benchmarks/report.py

clean:
	rm -rf $(VENV) out .pytest_cache build/docs build/jupyter_execute docs/api/generated
