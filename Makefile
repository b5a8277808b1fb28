# The README's commands. Everything runs with Debian's /usr/bin/python3 (the interpreter Debian's
# Blender embeds), never a pyenv/venv python without numpy.
PYTHON  ?= /usr/bin/python3
BLENDER ?= blender
BUILD   ?= build
JOBS    ?= 2
PIP_INSTALL = $(PYTHON) -m pip install --no-build-isolation --no-deps --break-system-packages --quiet
VERSION := $(shell cat VERSION)
# ccache where installed (scripts/setup-debian.sh installs it): a compile that another build of
# this run has done (the library in `build`, `pip install .`, the CHOLMOD-from-source builds), or
# an earlier run in any clone (paths relative to the checkout), is not done again. The chroots'
# builds (no ccache there) drop the launcher (scripts/build-portable.sh).
# Recursive (=): looked up when a recipe runs, after `setup` has installed it on a fresh machine.
CCACHE = $(shell command -v ccache 2>/dev/null)
export CMAKE_C_COMPILER_LAUNCHER = $(CCACHE)
export CMAKE_CXX_COMPILER_LAUNCHER = $(CCACHE)
export CCACHE_BASEDIR = $(CURDIR)
# The shipped modules and the chroots they are built and tested in (made afresh in a fresh clone).
PORTABLE ?= $(BUILD)/portable
export BDI_CHROOTS ?= $(CURDIR)/$(PORTABLE)/chroots
EXTENSION_ZIP = dist/bdinterp_blender-$(VERSION)-extension.zip
LEGACY_ZIP    = dist/bdinterp_blender-$(VERSION)-legacy-py311.zip

.PHONY: setup setup-demo build install portable addon demo test test-cpp test-python test-blender \
        test-blender-43 test-blender-52 test-runtime test-toolchain-sid test-wheel gallery bench clean \
        suitesparse test-cholmod-source test-windows test-libcxx test-wheel-source test-extension-split \
        bench-cholmod-source

setup:            ## install Debian packages (apt)
	bash scripts/setup-debian.sh

setup-demo:       ## install only the Debian packages `make demo` needs (apt)
	bash scripts/setup-debian.sh demo

# The host build: the C++ library (+ its tests) and the in-tree Python module python/bdinterp/_core.
CONFIGURE = cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=$(PYTHON) \
            -DBDINTERP_PYTHON_OUTPUT_DIR=$(CURDIR)/python/bdinterp
build: setup      ## C++ library, tests and the in-tree Python module
	$(CONFIGURE) -DBDINTERP_TESTS=ON -DBDINTERP_SPRITE=ON -DCMAKE_UNITY_BUILD=OFF
	cmake --build $(BUILD) -j $(JOBS)

install: setup    ## the Python package bdinterp (with its compiled module) for /usr/bin/python3
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) $(PIP_INSTALL) .

portable: setup   ## the shipped _core modules (CPython 3.11, 3.13, 3.14; linux-x64) built in Debian 11 (root)
	bash scripts/build-portable.sh $(PORTABLE)

addon: portable   ## dist/: legacy zip, extension zip, wheels; prints the .so audit table
	$(PYTHON) scripts/build_addon.py --portable $(PORTABLE)

# The demo runs on the host build (addon/ and python/ of this checkout), not on the shipped zips.
# It needs no sprite mesher; a unity build (16 sources a unit) halves the compile's CPU time and
# gives bit-identical frames.
demo: setup-demo  ## the main job: bake in-betweens of an example into out/example.blend + pictures
	$(CONFIGURE) -DBDINTERP_TESTS=OFF -DBDINTERP_SPRITE=OFF -DCMAKE_UNITY_BUILD=ON \
	    -DCMAKE_UNITY_BUILD_BATCH_SIZE=16
	cmake --build $(BUILD) -j $(JOBS) --target _core
	$(BLENDER) --background --factory-startup --python-exit-code 1 --python scripts/bake_example.py \
	    -- --out out --core python

test-cpp: build
	cd $(BUILD) && ctest --output-on-failure
	# the installed library works for a stand-alone CMake project
	cmake --install $(BUILD) --prefix $(BUILD)/prefix >/dev/null
	cmake -S examples/cpp -B $(BUILD)/cpp-example -DCMAKE_PREFIX_PATH=$(CURDIR)/$(BUILD)/prefix >/dev/null
	cmake --build $(BUILD)/cpp-example
	$(BUILD)/cpp-example/bend_bar
	# the public API is self-contained: every installed header compiles on its own
	for h in $(BUILD)/prefix/include/bdinterp/*.h; do echo "#include \"bdinterp/$$(basename $$h)\"" | \
	  $(CXX) -std=c++17 -fsyntax-only -x c++ -I$(BUILD)/prefix/include -I/usr/include/eigen3 - || exit 1; done
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
	$(MAKE) test-runtime RUNTIME=blender-3.4

test-blender-43: addon  ## Blender 4.3 / Python 3.13 in a Debian 13 chroot on the extension zip
	bash scripts/test-blender-chroot.sh trixie $(EXTENSION_ZIP) -q
	$(MAKE) test-runtime RUNTIME=blender-4.3

test-blender-52: addon  ## Blender 5.2 LTS / Python 3.14 in a Debian unstable chroot on the extension zip
	bash scripts/test-blender-chroot.sh sid $(EXTENSION_ZIP) -q
	$(MAKE) test-runtime RUNTIME=blender-5.2

test-runtime:  ## the glTF files a Blender suite exported (build/runtime/$(RUNTIME)) validated and played in three.js (node)
	BDI_RUNTIME_DIR=build/runtime/$(RUNTIME) $(PYTHON) -m pytest -q tests/runtime

test-toolchain-sid: setup  ## C++ and Python tests with Eigen 5, SuiteSparse 7, pybind11 3, numpy 2 (sid chroot)
	bash scripts/test-toolchain-chroot.sh -q

test-wheel: addon  ## `pip wheel .` and the portable wheel install into a Python without SuiteSparse
	bash scripts/test-wheel.sh $(BUILD)/wheel-test

test: test-cpp test-python test-blender test-blender-43 test-blender-52 test-toolchain-sid test-wheel \
      fuzz asan test-cholmod-source test-windows test-libcxx test-wheel-source \
      test-extension-split  ## everything CI runs

gallery: install  ## regenerate docs/gallery (README pictures and tables)
	$(PYTHON) scripts/make_gallery.py

# In a variable: a comma inside $(or ...) would split its arguments (only --sizes=5000 ran).
BENCH_SIZES = --sizes=5000,50000,500000
bench: setup      ## speed table (docs/BENCHMARKS.md); BENCH_ARGS="--sizes=5000 --reps=3" for a short run
	cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DBDINTERP_BENCH=ON -DBDINTERP_PYTHON=OFF -DBDINTERP_TESTS=OFF
	cmake --build build-bench -j $(JOBS) --target bdinterp_bench
	build-bench/bdinterp_bench $(or $(BENCH_ARGS),$(BENCH_SIZES) --reps=3)

clean:
	rm -rf $(BUILD) build-pip build-bench build-bench-source dist out

# --- other platforms (docs/PLATFORMS.md) ----------------------------------------------------------
# CHOLMOD from Debian 13's SuiteSparse 7 source (one tree for all: the one `make portable` fetches),
# without BLAS/LAPACK: simplicial factors only, as on a platform with no BLAS at hand.
SUITESPARSE    = $(PORTABLE)/suitesparse
SOURCE_CHOLMOD = -DBDINTERP_SUITESPARSE_SOURCE=$(CURDIR)/$(SUITESPARSE)/src -DBDINTERP_CHOLMOD_BLAS=OFF
GTEST_SOURCE   = -DBDINTERP_GTEST_SOURCE=/usr/src/googletest
WINE          ?= /usr/lib/wine/wine64
WINE_ENV       = WINEPREFIX=$(CURDIR)/$(BUILD)/wineprefix WINEDEBUG=-all
suitesparse: setup  ## SuiteSparse 7 source (Debian 13's, through the trixie chroot's apt; root)
	bash scripts/make-chroot.sh blender $(BDI_CHROOTS)/trixie
	bash scripts/fetch-suitesparse.sh $(SUITESPARSE) $(BDI_CHROOTS)/trixie

test-cholmod-source: suitesparse  ## the C++ suite with CHOLMOD built from source, no BLAS (Linux)
	cmake -S . -B $(BUILD)/cholmod-source -DCMAKE_BUILD_TYPE=Release -DBDINTERP_PYTHON=OFF $(SOURCE_CHOLMOD)
	cmake --build $(BUILD)/cholmod-source -j $(JOBS) --target bdinterp_tests
	$(BUILD)/cholmod-source/bdinterp_tests

test-windows: suitesparse  ## the C++ suite cross-built with MinGW-w64 (static .exe), run under wine64
	cmake -S . -B $(BUILD)/windows -DCMAKE_TOOLCHAIN_FILE=cmake/mingw-w64-x86_64.cmake \
	      -DCMAKE_BUILD_TYPE=Release -DBDINTERP_PYTHON=OFF -DBDINTERP_SPRITE=OFF $(SOURCE_CHOLMOD) $(GTEST_SOURCE) \
	      -DCMAKE_DISABLE_FIND_PACKAGE_OpenMP=ON
	cmake --build $(BUILD)/windows -j $(JOBS) --target bdinterp_tests
	$(WINE_ENV) $(WINE) $(BUILD)/windows/bdinterp_tests.exe

test-libcxx: setup  ## the C++ suite with clang and libc++ (Apple's C++ library); macOS probe syntax
	cmake -S . -B $(BUILD)/libcxx -DCMAKE_BUILD_TYPE=Release -DBDINTERP_PYTHON=OFF $(GTEST_SOURCE) \
	      -DCMAKE_C_COMPILER=$(CLANG) -DCMAKE_CXX_COMPILER=$(CLANGXX) -DCMAKE_CXX_FLAGS=-stdlib=libc++
	cmake --build $(BUILD)/libcxx -j $(JOBS) --target bdinterp_tests
	$(BUILD)/libcxx/bdinterp_tests
	# macOS's probes: compiled against declarations of Apple's calls only (tests/cpp/macos_sdk), not run
	$(CLANGXX) -std=c++17 -stdlib=libc++ -Wall -Wextra -Werror -fsyntax-only -D__APPLE__ \
	      -Itests/cpp/macos_sdk -Icpp/include -Icpp/src cpp/src/parallel/machine_probe_macos.cpp

test-wheel-source: suitesparse  ## the wheels workflow's linux-x64 build commands; its wheel's Python suite
	bash scripts/test-wheel-source.sh $(BUILD)/wheel-source $(SUITESPARSE)

test-extension-split: addon  ## the wheels' extension split per platform by Blender 4.3 (trixie chroot)
	bash scripts/extension-split.sh dist $(BUILD)/extension-split --chroot $(BDI_CHROOTS)/trixie

bench-cholmod-source: suitesparse  ## speed: Debian's CHOLMOD and CHOLMOD from source without BLAS, one session
	cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DBDINTERP_BENCH=ON -DBDINTERP_PYTHON=OFF -DBDINTERP_TESTS=OFF
	cmake -S . -B build-bench-source -DCMAKE_BUILD_TYPE=Release -DBDINTERP_BENCH=ON -DBDINTERP_PYTHON=OFF \
	      -DBDINTERP_TESTS=OFF $(SOURCE_CHOLMOD)
	cmake --build build-bench -j $(JOBS) --target bdinterp_bench
	cmake --build build-bench-source -j $(JOBS) --target bdinterp_bench
	for b in build-bench build-bench-source; do echo "== $$b"; \
	  $$b/bdinterp_bench $(or $(BENCH_ARGS),$(BENCH_SIZES) --reps=3 --busy=) | sed -n '/^Summary/,$$p'; done

# --- fuzzing and sanitizers (docs/FUZZING.md) -----------------------------------------------------
# `make fuzz`: both libFuzzer targets of tests/fuzz (clang, ASan + UBSan), each run FUZZ_SECONDS on a
# copy of its seed corpus; `make asan`: the C++ test suite built with ASan + UBSan and run.
CLANGXX      ?= clang++
CLANG        ?= clang
FUZZ_SECONDS ?= 60
FUZZ_BUILD   ?= build-fuzz
FUZZ_TARGETS  = fuzz_raw_input fuzz_disk_targets
SANITIZE      = -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
FUZZ_FLAGS    = -std=c++17 -O1 -g $(SANITIZE) -Icpp/include -Icpp/src -Itests/cpp -I/usr/include/eigen3 \
                -I/usr/include/suitesparse
# the Linux build's sources: the Windows and macOS probes do not compile here; no sprite mesher (CGAL)
FUZZ_SOURCES  = $(filter-out cpp/src/parallel/machine_probe_windows.cpp cpp/src/parallel/machine_probe_macos.cpp \
                  cpp/src/sprite/%,$(wildcard cpp/src/*/*.cpp))
FUZZ_OBJECTS  = $(patsubst cpp/src/%.cpp,$(FUZZ_BUILD)/%.o,$(FUZZ_SOURCES))

.PHONY: fuzz fuzz-build fuzz-known asan
.SECONDARY: $(FUZZ_OBJECTS)
$(FUZZ_BUILD)/%.o: cpp/src/%.cpp $(wildcard cpp/include/bdinterp/*.h cpp/src/*/*.h)
	@mkdir -p $(dir $@)
	$(CCACHE) $(CLANGXX) $(FUZZ_FLAGS) -fsanitize=fuzzer-no-link -c $< -o $@
$(FUZZ_BUILD)/%: tests/fuzz/%.cpp tests/fuzz/fuzz_common.h $(FUZZ_OBJECTS)
	$(CLANGXX) $(FUZZ_FLAGS) -fsanitize=fuzzer $< $(FUZZ_OBJECTS) -lcholmod -lpthread -o $@
fuzz-build: $(addprefix $(FUZZ_BUILD)/,$(FUZZ_TARGETS))
fuzz: fuzz-build  ## each fuzz target for FUZZ_SECONDS (a finding fails, its input is in $(FUZZ_BUILD))
	for t in $(FUZZ_TARGETS); do \
	  rm -rf $(FUZZ_BUILD)/corpus-$$t && mkdir -p $(FUZZ_BUILD)/corpus-$$t && \
	  cp tests/fuzz/corpus/$$t/* $(FUZZ_BUILD)/corpus-$$t/ && \
	  $(FUZZ_BUILD)/$$t -max_total_time=$(FUZZ_SECONDS) -max_len=4096 -timeout=20 -rss_limit_mb=4096 \
	      -print_final_stats=1 -artifact_prefix=$(FUZZ_BUILD)/$$t- \
	      $(FUZZ_BUILD)/corpus-$$t tests/fuzz/corpus/$$t || exit 1; \
	done
fuzz-known: fuzz-build  ## replays tests/fuzz/known (core findings not yet fixed): which still fail
	@for t in $(FUZZ_TARGETS); do for f in tests/fuzz/known/$$t/*; do [ -e "$$f" ] || continue; \
	  if $(FUZZ_BUILD)/$$t $$f >/dev/null 2>&1; then echo "fixed:   $$f"; else echo "failing: $$f"; fi; \
	done; done
asan: setup       ## the C++ tests under AddressSanitizer + UndefinedBehaviorSanitizer
	cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBDINTERP_PYTHON=OFF \
	      -DCMAKE_CXX_COMPILER=$(CLANGXX) -DCMAKE_CXX_FLAGS="$(SANITIZE)"
	cmake --build build-asan -j $(JOBS) --target bdinterp_tests
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 build-asan/bdinterp_tests
