# Two commands for a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
# pip would compile every installed module, on one core: 17 of the 33 s of CPU of a fresh core
# install (load ~8). `make run` compiles what its job imports, `make test` all (`bytecode`).
PIP    := $(PY) -m pip install --quiet --disable-pip-version-check --no-compile
# `make run`: the core alone (pip install fingerpad: solve, predict and the figures).
CORE   := $(VENV)/.core-stamp
# `make test`, `make docs`: every extra, the test and documentation stacks (the `test` extra).
STAMP  := $(VENV)/.installed-stamp

.PHONY: run test test-slow docs bench bytecode dist clean

$(CORE): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PIP) -e .
	$(PY) -m compileall -q -j 0 src > /dev/null
	touch $(CORE)

# After `make run` the core is there: this adds the rest (a stamp of its own, so `make test`
# after `make run` installs the extras; pyproject.toml newer than either redoes it).
$(STAMP): pyproject.toml $(CORE)
	$(PIP) -e ".[test]"
	$(MAKE) --no-print-directory bytecode
	touch $(STAMP)

# The bytecode of the package and of everything installed, compiled in parallel (pip is told not
# to, serially): where the environment sets PYTHONDONTWRITEBYTECODE, a module without it would be
# compiled on every start (~0.06 s of CPU for `fingerpad solve` for the package alone, issue 23;
# seconds for NumPy, SciPy and pandas). Python recompiles any module edited since, in memory.
# A file some installed package ships that does not compile is skipped, as pip skips it.
bytecode:
	$(PY) -m compileall -q -j 0 src > /dev/null
	$(PY) -m compileall -q -j 0 $(VENV)/lib/python*/site-packages > /dev/null || true

# The job writes the bytecode of the modules it imports into .venv (where the environment sets
# PYTHONDONTWRITEBYTECODE, as pip would have written it): later starts read it.
run: $(CORE)
	env -u PYTHONDONTWRITEBYTECODE $(VENV)/bin/fingerpad run-default --out out/run

test: $(STAMP)
	$(PY) -m pytest -q -m "not slow" --durations=25

test-slow: $(STAMP)
	$(PY) -m pytest -q -m slow

# The documentation site (docs/ -> build/docs/index.html): Markdown pages, the API reference from
# the docstrings, the tutorial notebook executed. Warnings are errors, as in tests/test_docs.py.
docs: $(STAMP)
	$(PY) -m sphinx -b html -W --keep-going -q docs build/docs
	@echo "the site: build/docs/index.html"

bench: $(STAMP) bytecode
	$(PIP) -e ".[bench]"
	$(PY) benchmarks/bench_solver.py --grids 1024,2048 --memory 4096
	$(PY) benchmarks/bench_predict.py
	$(PY) benchmarks/bench_population.py
	$(PY) benchmarks/bench_startup.py
	$(PY) benchmarks/bench_sweep.py
	$(PY) benchmarks/bench_population_sweep.py
	$(PY) benchmarks/bench_map_speed.py
	$(PY) benchmarks/bench_batch_fft.py
	$(PY) benchmarks/bench_sweep_scheduler.py
	$(PY) benchmarks/bench_analyse.py
	$(PY) benchmarks/bench_adhesion.py
	$(PY) benchmarks/bench_population_adhesion.py
	$(PY) benchmarks/pull_in_orders.py
	$(PY) benchmarks/bench_deflection.py
	test ! -f benchmarks/bench_explorer.py || $(PY) benchmarks/bench_explorer.py
	$(PY) benchmarks/report.py

# The release files: an sdist and a wheel in dist/ (tests/test_release.py installs the wheel
# into a fresh environment with the core alone).
dist: $(STAMP)
	rm -rf dist
	$(PY) -m build --outdir dist .

clean:
	rm -rf $(VENV) out dist .pytest_cache build/docs build/jupyter_execute docs/api/generated
