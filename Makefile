# SPDX-License-Identifier: MIT
# The README's two commands: `make demo` and `make test`. Each installs what is
# missing (scripts/install-deps.sh), builds, and (re)generates the default dataset.
BUILD  ?= build
JOBS   ?= $(shell nproc)
CMAKE_FLAGS ?=
DATASET := datasets/change5
GEN     := $(BUILD)/generate_change5

.PHONY: all deps build dataset demo test bench clean

all: build

deps:
	@scripts/install-deps.sh

$(BUILD)/build.ninja: | deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

# The dataset is regenerated when it is missing or older than the generator binary.
dataset: build
	@[ $(DATASET)/scene.json -nt $(GEN) ] || $(GEN) $(DATASET)

demo: dataset
	$(BUILD)/plancheck scene $(DATASET)/scene.json
	$(BUILD)/plancheck verify $(DATASET)/scene.json $(DATASET)/plans/*.csv --out $(BUILD)/demo-out; \
	  status=$$?; [ $$status -le 1 ] || exit $$status

test: dataset
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 1800

# Micro benchmarks (each checks its answer first), then Table 3 beside FCL
# (answers checked state by state before anything is timed). Nothing else
# should run on the machine meanwhile: the numbers are wall-clock medians.
bench: dataset
	$(BUILD)/plancheck_bench --benchmark_min_time=0.2
	$(BUILD)/plancheck bench $(DATASET)/scene.json --fcl --fcl-repetitions 5 --repetitions 9 --json $(BUILD)/table3.json
	$(BUILD)/plancheck_regolith_bench $(DATASET)
	$(BUILD)/plancheck_continuous_bench $(DATASET)

clean:
	rm -rf $(BUILD) $(DATASET)
