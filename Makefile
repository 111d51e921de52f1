# tagbench: the two commands are `make test` and `make bench` (see README.md).
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release
# `make test` also runs the whole suite under AddressSanitizer + UndefinedBehaviorSanitizer in this
# second tree. -O1 with line tables only (-g1): the instrumented build and suite stay well inside
# CI's time budget, and reports still name file and line. The sanitizer options (and the LSan
# suppressions, testing/lsan.supp) reach every test through ctest (TAGBENCH_SANITIZE in CMakeLists.txt).
ASAN_BUILD ?= build-asan
ASAN_CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" \
                    -DTAGBENCH_SANITIZE=ON

.PHONY: all deps configure build test test-asan bench families clean install deb

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)
	@$(MAKE) --no-print-directory test-asan

# The sanitizer pass alone (`make test` runs it after the normal suite).
test-asan: deps
	@cmake -S . -B $(ASAN_BUILD) $(ASAN_CMAKE_FLAGS) >/dev/null
	@cmake --build $(ASAN_BUILD) -j$(JOBS)
	cd $(ASAN_BUILD) && ctest --output-on-failure -j$(JOBS)

# Installs what `make` built (library, headers, program, families, CMake and pkg-config files, the
# Python module) under PREFIX, without rebuilding anything else (cmake --install).
PREFIX ?= /usr/local
install: build
	cmake --install $(BUILD) --prefix $(PREFIX)

# Debian packages tagbench, libtagbench-dev and python3-tagbench in $(BUILD)/deb (cmake/packaging.cmake).
deb: build
	cd $(BUILD) && cpack -G DEB -B deb

# Regenerates everything in results/ (CSV, JSON sidecars, PNG plots) and the README's tables.
bench: build
	@scripts/run-bench.sh $(BUILD)

# Continues (or starts) the long lexicode runs of the shipped families; resumable at any time.
families: build
	@scripts/generate-families.sh $(BUILD)/cli/tagbench

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)

# Fuzzing (fuzz/README.md): the libFuzzer targets, built with clang in their own tree, each run for
# FUZZ_SECONDS; every run is a row of results/fuzz.csv (scripts/fuzz.py). FUZZ_TARGETS picks some
# (default all). `make test` replays the seeds and crash regressions without clang.
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_TARGETS ?=
FUZZ_CMAKE_FLAGS ?= -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DTAGBENCH_FUZZ=ON \
                    -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g"
.PHONY: fuzz
fuzz:
	@scripts/install-deps.sh --fuzz
	@cmake -S . -B $(FUZZ_BUILD) $(FUZZ_CMAKE_FLAGS) >/dev/null
	@cmake --build $(FUZZ_BUILD) -j$(JOBS) --target fuzz_all
	@scripts/fuzz.py --build $(FUZZ_BUILD) --seconds $(FUZZ_SECONDS) $(FUZZ_TARGETS)
