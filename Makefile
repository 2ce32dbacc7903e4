# Seamless AO: one entry point for setup, demo, tests, benchmarks and packaging.
#
#   make demo        set up .venv/5.0 and bake the built-in demo scene into out/
#   make batch ARGS="assets/ --output-dir baked/"   bake a folder of assets (README, Pipelines)
#   make test        run the test suite on Blender 5.0, 4.2 LTS and 5.2 (bpy wheels), then make test-real
#   make test BLENDERS=5.0       ... on one Blender only (and test-real)
#   make test-real   the tests that run a real blender binary (Debian's, in a root built once; needs root)
#   make test-gui    ... only those in a Blender window (Xvfb), driven with the mouse and keyboard
#   make test-fast   only tests/core (numpy + mathutils, no Blender data) on Blender 5.0
#   make bench       every benchmark, each writing its page into docs/bench/; then docs/benchmarks.md
#   make docs        docs/settings.md, docs/constants.md, docs/tested.md, read off the code
#   make extension   download the xatlas wheels and build the installable zips (dist/)
#
# Every target creates what it needs: a virtualenv per Blender version under
# .venv/<version>, with the pinned wheels of requirements/blender-<version>.txt.
# The wheels are downloaded once into a wheelhouse inside the user's pip cache
# (never into the repository), then installed from there without the index.

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := help

BLENDER ?= 5.0
BLENDERS ?= 5.0 4.2 5.2
PYTEST_ARGS ?=

# Python version each bpy wheel is built for.
PYVER_4.2 := 3.11
PYVER_5.0 := 3.11
PYVER_5.2 := 3.13

# The first interpreter of that version that actually runs: on PATH, or pyenv's.
find_python = $(shell for c in python$(1) $$(pyenv root 2>/dev/null)/versions/$(1)*/bin/python$(1) $(HOME)/.pyenv/versions/$(1)*/bin/python$(1); do \
    if "$$c" -c "import sys; assert sys.version_info[:2] == tuple(map(int, '$(1)'.split('.')))" >/dev/null 2>&1; then echo "$$c"; break; fi; done)

WHEELHOUSE ?= $(shell python3 -m pip cache dir 2>/dev/null || echo $(HOME)/.cache/pip)/seamless-ao-wheelhouse

venv_dir = .venv/$(1)
venv_python = .venv/$(1)/bin/python

.PHONY: help setup demo batch test test-fast test-setup test-one test-real test-gui docs bench extension validate clean

help:
	@sed -n '3,11p' Makefile | sed 's/^# \{0,1\}//'

# .venv/<version>/.installed is rebuilt when the pins change.
.venv/%/.installed: requirements/blender-%.txt
	@py="$(call find_python,$(PYVER_$*))"; \
	if [ -z "$$py" ]; then echo "error: Blender $* needs Python $(PYVER_$*), which was not found (on PATH or in pyenv)." >&2; exit 1; fi; \
	echo "== Blender $*: virtualenv .venv/$* with $$py"; \
	rm -rf .venv/$*; "$$py" -m venv .venv/$*; \
	mkdir -p "$(WHEELHOUSE)"; \
	echo "== Blender $*: fetching pinned wheels into $(WHEELHOUSE) (cached after the first time)"; \
	.venv/$*/bin/python -m pip download --quiet --only-binary=:all: -d "$(WHEELHOUSE)" -r requirements/blender-$*.txt; \
	echo "== Blender $*: installing from the wheelhouse"; \
	.venv/$*/bin/python -m pip install --quiet --no-index --find-links "$(WHEELHOUSE)" -r requirements/blender-$*.txt; \
	touch $@

setup: .venv/$(BLENDER)/.installed

demo: .venv/5.0/.installed
	$(call venv_python,5.0) operators/launchers/launch.py demo --output-dir out

# The batch command without a Blender install: make batch ARGS="assets/ --output-dir baked/ --jobs 2"
batch: .venv/5.0/.installed
	$(call venv_python,5.0) operators/launchers/launch.py command batch $(ARGS)

# Blenders whose Python this machine has, and those it lacks (each is said; under CI a lack is an error).
AVAILABLE = $(foreach v,$(BLENDERS),$(if $(call find_python,$(PYVER_$(v))),$(v)))
MISSING = $(filter-out $(AVAILABLE),$(BLENDERS))

# Every Blender's virtualenv and the shared tools are set up first, one after another.  Then the first
# Blender's session (5.0, with the heavy tests) runs in the foreground while the others run one after
# another beside it: a session keeps about one core busy and machines have two.  Their output is shown when
# they end.  The real binary's tests (a window among them) come last, alone.
test:
	@available="$(strip $(AVAILABLE))"; missing="$(strip $(MISSING))"; \
	$(foreach v,$(MISSING),echo "== Blender $(v): skipped: its bpy wheel needs Python $(PYVER_$(v)), which was not found (on PATH or in pyenv)" >&2;) \
	if [ -n "$$missing" ] && [ -n "$${CI:-}" ]; then echo "error: CI tests every Blender of BLENDERS ($(BLENDERS)); install the missing Python" >&2; exit 1; fi; \
	for v in $$available; do $(MAKE) --no-print-directory test-setup BLENDER=$$v; done; \
	set -- $$available; first="$${1:-}"; shift || true; rest="$$*"; side=""; log="$$(mktemp)"; status=0; \
	if [ -n "$$rest" ]; then \
	    echo "== Blender $$rest: beside Blender $$first, one after another (their output follows when they end)"; \
	    ( for v in $$rest; do $(MAKE) --no-print-directory test-one BLENDER=$$v || exit 1; done ) > "$$log" 2>&1 & side=$$!; \
	    trap 'kill $$side 2>/dev/null || true' EXIT; \
	fi; \
	if [ -n "$$first" ]; then $(MAKE) --no-print-directory test-one BLENDER=$$first || status=1; fi; \
	if [ -n "$$side" ]; then wait $$side || status=1; trap - EXIT; cat "$$log"; fi; \
	rm -f "$$log"; \
	if [ $$status -ne 0 ]; then echo "error: a Blender's tests failed (above)" >&2; exit 1; fi; \
	$(MAKE) --no-print-directory test-real; \
	if [ -n "$$missing" ]; then echo "== Tested Blender $${available:-none}; skipped $$missing (no Python for it here)"; fi

# Blender 5.0, which runs the heavy tests, also gets Dask for the farm tests (requirements/farm.txt).
test-setup: .venv/$(BLENDER)/.installed wheels/.downloaded .node/.installed $(if $(filter 5.0,$(BLENDER)),.venv/5.0/.farm)

test-one: test-setup
	@echo "== Blender $(BLENDER): pytest"
	$(call venv_python,$(BLENDER)) -m pytest tests --ignore=tests/real_blender $(PYTEST_ARGS)

# A real Blender binary: Debian's (trixie: 4.3.2) in a root built once per machine outside the repository
# (tests/scripts/make_blender_root.sh; needs root and debootstrap, which it installs with apt-get). Where the
# machine cannot build it, the tests are skipped with its sentence; under CI that is an error.
BLENDER_ROOT ?= $(HOME)/.cache/seamless-ao-blender-root
REAL_TESTS ?= tests/real_blender

test-real: .venv/5.0/.installed wheels/.downloaded .node/.installed
	@status=0; bash tests/scripts/make_blender_root.sh "$(BLENDER_ROOT)" || status=$$?; \
	if [ $$status -eq 3 ] && [ -n "$${CI:-}" ]; then echo "error: CI runs the real-Blender tests, and the root cannot be built here" >&2; exit 1; fi; \
	if [ $$status -eq 3 ]; then echo "== real Blender: skipped (the root cannot be built here)"; exit 0; fi; \
	if [ $$status -ne 0 ]; then echo "error: building the real-Blender root in $(BLENDER_ROOT) failed" >&2; exit 1; fi; \
	echo "== real Blender ($(BLENDER_ROOT)): pytest"; \
	SEAMLESS_AO_BLENDER_ROOT="$(BLENDER_ROOT)" $(call venv_python,5.0) -m pytest $(REAL_TESTS) $(PYTEST_ARGS)

test-gui:
	@$(MAKE) --no-print-directory test-real REAL_TESTS=tests/real_blender/test_gui.py

# The Khronos glTF validator (npm), pinned by requirements/gltf-validator/package-lock.json; the tests run it
# on every GLB they write.
.node/.installed: requirements/gltf-validator/package.json requirements/gltf-validator/package-lock.json
	@echo "== glTF validator: npm ci into .node/"
	@mkdir -p .node
	@cp requirements/gltf-validator/package.json requirements/gltf-validator/package-lock.json .node/
	@cd .node && npm ci --silent --no-audit --no-fund
	@touch $@

test-fast: .venv/5.0/.installed
	$(call venv_python,5.0) -m pytest tests/core $(PYTEST_ARGS)

.venv/5.0/.farm: .venv/5.0/.installed requirements/farm.txt
	@echo "== Blender 5.0: Dask for the batch on a cluster (requirements/farm.txt)"
	.venv/5.0/bin/python -m pip download --quiet --only-binary=:all: -d "$(WHEELHOUSE)" -r requirements/farm.txt -r requirements/blender-5.0.txt
	.venv/5.0/bin/python -m pip install --quiet --no-index --find-links "$(WHEELHOUSE)" -r requirements/farm.txt -r requirements/blender-5.0.txt
	touch $@

.venv/5.0/.bench: .venv/5.0/.installed .venv/5.0/.farm requirements/bench.txt
	.venv/5.0/bin/python -m pip download --quiet --only-binary=:all: -d "$(WHEELHOUSE)" -r requirements/bench.txt -r requirements/blender-5.0.txt
	.venv/5.0/bin/python -m pip install --quiet --no-index --find-links "$(WHEELHOUSE)" -r requirements/bench.txt -r requirements/blender-5.0.txt
	touch $@

# Every benchmark writes its page into docs/bench/; the last step assembles docs/benchmarks.md.
BENCHES ?= bench_meshes report bench_fixed_cost bench_atlas_space bench_atlas bench_rays bench_million bench_held_memory bench_texel_proxy bench_proxy_cells bench_clustering bench_assets bench_buried \
           bench_concave bench_blotch bench_adaptive bench_weighted bench_conventions bench_memory bench_occluders bench_objects \
           bench_batch bench_farm bench_file_size bench_cycles_margin bench_cycles_engine bench_cycles_caster bench_rings bench_denoise bench_viewport bench_window

bench: .venv/5.0/.bench
	@for b in $(BENCHES); do echo "== $$b"; $(call venv_python,5.0) tests/bench/$$b.py; done
	$(call venv_python,5.0) tests/bench/assemble.py

docs: .venv/5.0/.installed
	$(call venv_python,5.0) tests/scripts/write_docs.py

# ---------------------------------------------------------------------------
# Packaging: the zips bundle the xatlas wheels listed in blender_manifest.toml.

XATLAS := 0.0.11
XATLAS_PLATFORMS := manylinux_2_17_x86_64 win_amd64 macosx_11_0_arm64

wheels/.downloaded: blender_manifest.toml
	@mkdir -p wheels
	@for py in 311 313; do for plat in $(XATLAS_PLATFORMS); do \
	  python3 -m pip download --quiet --only-binary=:all: --no-deps --python-version $$py --platform $$plat \
	    -d wheels xatlas==$(XATLAS); done; done
	@touch $@

BLENDER_EXT = $$(ls .venv/$(BLENDER)/lib/python*/site-packages/bpy/*/scripts/addons_core/bl_pkg/cli/blender_ext.py)

validate: .venv/$(BLENDER)/.installed wheels/.downloaded
	$(call venv_python,$(BLENDER)) $(BLENDER_EXT) validate .

extension: .venv/$(BLENDER)/.installed wheels/.downloaded
	@mkdir -p dist
	$(call venv_python,$(BLENDER)) $(BLENDER_EXT) build --source-dir . --output-dir dist --split-platforms
	@ls -1 dist/*.zip

clean:
	rm -rf .venv .node wheels dist out .pytest_cache
