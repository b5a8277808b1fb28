# The README's commands. Everything runs with Debian's /usr/bin/python3 (the interpreter Debian's
# Blender embeds), never a pyenv/venv python without numpy.
PYTHON  ?= /usr/bin/python3
BLENDER ?= blender
BUILD   ?= build
JOBS    ?= 2
PIP_INSTALL = $(PYTHON) -m pip install --no-build-isolation --no-deps --break-system-packages --quiet
VERSION := $(shell cat VERSION)
# The shipped modules and the chroots they are built and tested in (made afresh in a fresh clone).
PORTABLE ?= $(BUILD)/portable
export BDI_CHROOTS ?= $(CURDIR)/$(PORTABLE)/chroots
EXTENSION_ZIP = dist/bdinterp_blender-$(VERSION)-extension.zip
LEGACY_ZIP    = dist/bdinterp_blender-$(VERSION)-legacy-py311.zip

.PHONY: setup build install portable addon demo test test-cpp test-python test-blender \
        test-blender-43 test-wheel gallery bench clean

setup:            ## install Debian packages (apt)
	bash scripts/setup-debian.sh

build: setup      ## C++ library, tests and the in-tree Python module
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=$(PYTHON) \
	      -DBDINTERP_PYTHON_OUTPUT_DIR=$(CURDIR)/python/bdinterp
	cmake --build $(BUILD) -j $(JOBS)

install: setup    ## the Python package bdinterp (with its compiled module) for /usr/bin/python3
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) $(PIP_INSTALL) .

portable: setup   ## the shipped _core modules (CPython 3.11, 3.13; linux-x64) built in Debian 11 (root)
	bash scripts/build-portable.sh $(PORTABLE)

addon: portable   ## dist/: legacy zip, extension zip, wheels; prints the .so audit table
	$(PYTHON) scripts/build_addon.py --portable $(PORTABLE)

demo: addon install ## the main job: bake in-betweens of an example into out/example.blend + pictures
	$(BLENDER) --background --factory-startup --python-exit-code 1 --python scripts/bake_example.py -- --out out

test-cpp: build
	cd $(BUILD) && ctest --output-on-failure
	# the installed library works for a stand-alone CMake project
	cmake --install $(BUILD) --prefix $(BUILD)/prefix >/dev/null
	cmake -S examples/cpp -B $(BUILD)/cpp-example -DCMAKE_PREFIX_PATH=$(CURDIR)/$(BUILD)/prefix >/dev/null
	cmake --build $(BUILD)/cpp-example
	$(BUILD)/cpp-example/bend_bar
	# its version file accepts 0.x.* and refuses 0.(x+1); tests are off for add_subdirectory users
	cmake -S cmake/tests/version -B $(BUILD)/version-ok -DWANT=$(VERSION) -DEXPECT_FOUND=1 \
	      -DCMAKE_PREFIX_PATH=$(CURDIR)/$(BUILD)/prefix >/dev/null
	cmake -S cmake/tests/version -B $(BUILD)/version-next -DEXPECT_FOUND=0 \
	      -DWANT=$(word 1,$(subst ., ,$(VERSION))).$(shell echo $$(($(word 2,$(subst ., ,$(VERSION)))+1))) \
	      -DCMAKE_PREFIX_PATH=$(CURDIR)/$(BUILD)/prefix >/dev/null
	cmake -S cmake/tests/subproject -B $(BUILD)/subproject >/dev/null

test-python: install
	cd tests && $(PYTHON) -m pytest -q python

test-blender: addon  ## Blender 3.4 (Debian 12) on the legacy zip, host SuiteSparse/METIS hidden
	bash scripts/without-host-libs.sh $(BLENDER) --background --factory-startup --python-exit-code 1 \
	    --python tests/blender/run_blender_tests.py -- -q --zip $(LEGACY_ZIP)

test-blender-43: addon  ## Blender 4.3 / Python 3.13 in a Debian 13 chroot on the extension zip
	bash scripts/test-blender-chroot.sh $(EXTENSION_ZIP) -q

test-wheel: addon  ## `pip wheel .` and the portable wheel install into a Python without SuiteSparse
	bash scripts/test-wheel.sh $(BUILD)/wheel-test

test: test-cpp test-python test-blender test-blender-43 test-wheel  ## everything CI runs

gallery: install  ## regenerate docs/gallery (README pictures and tables)
	$(PYTHON) scripts/make_gallery.py

bench: setup      ## speed table (docs/BENCHMARKS.md); BENCH_ARGS="--sizes=5000 --reps=3" for a short run
	cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DBDINTERP_BENCH=ON -DBDINTERP_PYTHON=OFF -DBDINTERP_TESTS=OFF
	cmake --build build-bench -j $(JOBS) --target bdinterp_bench
	build-bench/bdinterp_bench $(or $(BENCH_ARGS),--sizes=5000,50000,500000 --reps=3)

clean:
	rm -rf $(BUILD) build-bench dist out
