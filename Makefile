# tagbench: the two commands are `make test` and `make bench` (see README.md).
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

.PHONY: all deps configure build test bench families clean

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

# Regenerates everything in results/ (CSV, JSON sidecars, PNG plots) and the README's tables.
bench: build
	@scripts/run-bench.sh $(BUILD)

# Continues (or starts) the long lexicode runs of the shipped families; resumable at any time.
families: build
	@scripts/generate-families.sh $(BUILD)/cli/tagbench

clean:
	rm -rf $(BUILD)
