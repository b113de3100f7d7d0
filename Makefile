# The project's commands. Each creates .venv when missing and installs the project into it.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
# pytest-xdist processes for `make test` (the suite runs on both cores of the reference machine)
TEST_WORKERS ?= 2
STAMP := $(VENV)/.installed-$(shell $(PYTHON) -c "import hashlib,sys;print(hashlib.sha1(open('pyproject.toml','rb').read()).hexdigest()[:12])")

.PHONY: test demo validate bench bench-peers bench-peers-3d fuzz docs clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[all]'
	# the numba kernels compiled into their on-disk cache once (about 10-30 s), not in a first run
	$(VENV)/bin/ibfem compile --quiet
	rm -f $(VENV)/.installed-* && touch $(STAMP)

test: $(STAMP)
	MPLBACKEND=Agg $(PY) -m pytest -m "not slow" -n $(TEST_WORKERS) --dist worksteal

demo: $(STAMP)
	MPLBACKEND=Agg $(PY) -m ibfem.solver.reports.demo

validate: $(STAMP)
	MPLBACKEND=Agg $(PY) -m ibfem.solver.reports.validate
	MPLBACKEND=Agg $(PY) -m ibfem.solver.reports.validate_solid
	MPLBACKEND=Agg $(PY) -m ibfem.solver.reports.validate_fretting --out out/validation_fretting
	MPLBACKEND=Agg $(PY) -m pytest -m slow -q tests/test_contact2d_validation.py tests/test_fretting.py \
		tests/test_fretting_pressure.py tests/test_accuracy_reference.py tests/test_size_estimate_separator.py \
		tests/test_size_estimate_planes.py
	# the 3D fretting's small-amplitude limit W ~ Q*^3 on the edge ring (about 12 minutes, 1.9 GB)
	MPLBACKEND=Agg $(PY) -m pytest -m slow -q tests/test_fretting_sphere.py -k edge_ring
	# 3D regions of general shape against closed forms and the half-space (rollers: about 20 minutes)
	MPLBACKEND=Agg $(PY) -m pytest -m slow -q tests/test_rounded_punch_3d.py tests/test_chamfered_punch_3d.py tests/test_contact3d_conformal.py \
		tests/test_line_contact.py

bench: $(STAMP)
	MPLBACKEND=Agg $(PY) benchmarks/run_all.py

# the peer study (NGSolve beside ibfem, docs/peers.md); installs the `peers` extra on first use
bench-peers: $(STAMP)
	$(PY) -c "import ngsolve" 2>/dev/null || $(PY) -m pip install --quiet -e '.[peers]'
	MPLBACKEND=Agg $(PY) benchmarks/peers.py

# the 3D peer study (quarter half ball on a block, NGSolve P2 tetrahedra beside ibfem)
bench-peers-3d: $(STAMP)
	$(PY) -c "import ngsolve" 2>/dev/null || $(PY) -m pip install --quiet -e '.[peers]'
	MPLBACKEND=Agg $(PY) benchmarks/peers.py --problem sphere3d

# the long fuzz campaign (FUZZ_MINUTES, default 10)
fuzz: $(STAMP)
	MPLBACKEND=Agg IBFEM_FUZZ_MINUTES=$${FUZZ_MINUTES:-10} $(PY) -m pytest tests/fuzz -m "fuzz_long or not slow" -p no:cacheprovider

# the documentation site (MkDocs) into site/, warnings and broken links as errors; installs the `docs`
# extra on first use
docs: $(STAMP)
	$(PY) -c "import mkdocs, material, mkdocstrings_handlers.python" 2>/dev/null || $(PY) -m pip install --quiet -e '.[docs]'
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict --quiet

clean:
	rm -rf $(VENV) build site *.egg-info .pytest_cache .hypothesis
