# Two entry points for a fresh machine with Python 3.11: `make run` and `make test`.
PYTHON ?= python3.11
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.exobench-installed

.PHONY: run test test-fast lint lock clean-results

# pip installs uv from its hashed lines in the lock; uv installs the whole lock, hashes required
# (the same wheels pip would take; about 22 s in all, with compileall). compileall writes the .pyc
# files of every installed module but the packages' own test suites: without them, where
# PYTHONDONTWRITEBYTECODE is set, every job and test compiles numpy, pandas, SciPy and Matplotlib
# again (about 6 s per process). The package's own modules are compiled too (src/, in the editable
# install: about 0.08 s of each job's start); a module edited later is compiled again on each
# import where PYTHONDONTWRITEBYTECODE is set.
$(STAMP): environment.lock pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	sed -n '/^uv==/,/# via/p' environment.lock > $(VENV)/uv.lock
	$(BIN)/python -m pip install --quiet --require-hashes --no-deps -r $(VENV)/uv.lock
	$(BIN)/uv pip install --quiet --python $(BIN)/python --require-hashes --no-deps -r environment.lock
	$(BIN)/python -m compileall -q -j 0 -x 'site-packages/.+/tests?/' $$($(BIN)/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])') > /dev/null
	$(BIN)/uv pip install --quiet --python $(BIN)/python --no-deps --no-build-isolation -e .
	$(BIN)/python -m compileall -q src > /dev/null
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/snakemake --cores 2

test: $(STAMP)
	$(BIN)/ruff check src tests workflow/scripts
	$(BIN)/ruff format --check src tests workflow/scripts
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(BIN)/snakemake --lint
	$(BIN)/pytest -n 2 --dist loadgroup --durations=20

# Unit tier: every test that runs no whole workflow and no long fuzz loop (under 60 s).
test-fast: $(STAMP)
	$(BIN)/pytest -n 2 -m "not slow"

lock: $(STAMP)
	$(BIN)/uv pip compile --python-version 3.11 --generate-hashes requirements.in -o environment.lock

clean-results:
	rm -rf results/* .snakemake
