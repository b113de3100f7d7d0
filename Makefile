# Commands of SPEC section 1. Each creates .venv when missing and installs the project into it.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed-$(shell $(PYTHON) -c "import hashlib,sys;print(hashlib.sha1(open('pyproject.toml','rb').read()).hexdigest()[:12])")

.PHONY: test demo validate bench clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[all]'
	rm -f $(VENV)/.installed-* && touch $(STAMP)

test: $(STAMP)
	MPLBACKEND=Agg $(PY) -m pytest -m "not slow"

demo: $(STAMP)
	MPLBACKEND=Agg $(PY) -m solver.reports.demo

validate: $(STAMP)
	MPLBACKEND=Agg $(PY) -m solver.reports.validate

bench: $(STAMP)
	MPLBACKEND=Agg $(PY) benchmarks/run_all.py

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache .hypothesis
