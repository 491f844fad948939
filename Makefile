# SPDX-License-Identifier: MIT
# The README's two commands: `make demo` and `make test`. Each installs what is
# missing (scripts/install-deps.sh), builds, and (re)generates the default dataset.
BUILD  ?= build
JOBS   ?= $(shell nproc)
CMAKE_FLAGS ?=
DATASET := datasets/change5
GEN     := $(BUILD)/generate_change5

# Sanitizer and fuzz builds (docs/development.md "Sanitizers and fuzzing"): each its own
# build folder, building only what its tests need (no benchmarks).
ASAN_BUILD ?= build-asan
TSAN_BUILD ?= build-tsan
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 60
# fuzz_model forks an importer child per input (src/scene/isolate.h), about 60
# inputs a second under ASan against thousands for the others: it gets longer.
FUZZ_MODEL_SECONDS ?= 120
# fuzz_urdf also forks an importer per mesh it resolves: a modest budget.
FUZZ_URDF_SECONDS ?= 45
FUZZ_TARGETS ?= scene plan model dem verify urdf partial
# -O1, line tables only (-g1): readable reports, lighter builds. -O1 is ASan's
# advice; here it compiles the heaviest test file in 42 s of CPU against 72-77 s
# at -O2, and the ASan suites ran 455 s against 447 s at -O2 (2026-11-28).
# They embed the Release build's viewer bundle (no second npm ci) and skip the
# browser tests (the Release run has them); the page writer is still tested.
SAN_CMAKE := -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
             -DPLANCHECK_BUILD_BENCH=OFF -DPLANCHECK_VIEWER=OFF -DPLANCHECK_BROWSER_TESTS=OFF \
             -DPLANCHECK_VIEWER_BUNDLE=$(CURDIR)/$(BUILD)/viewer/plancheck-viewer.js $(CMAKE_FLAGS)
export ASAN_OPTIONS ?= detect_leaks=1:abort_on_error=0:strict_string_checks=1
export UBSAN_OPTIONS ?= print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS ?= suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0
export TSAN_OPTIONS ?= halt_on_error=1:second_deadlock_stack=1:suppressions=$(CURDIR)/tests/tsan.supp

.PHONY: all deps build dataset demo test test-release test-asan test-tsan fuzz fuzz-build bench clean

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

# Everything CI runs, in this order; each step is also a target of its own.
# A failing step does not stop the later ones (CI shows every failure), but
# fails the whole. The time of each stage is printed at the end.
TEST_STEPS ?= test-release test-asan test-tsan fuzz
test:
	@failed=; times=; t_all=$$(date +%s); for step in $(TEST_STEPS); do \
	  echo "=== make $$step ($$(date +%T))"; t0=$$(date +%s); \
	  $(MAKE) --no-print-directory $$step || failed="$$failed $$step"; \
	  times="$$times$$(printf '  %-13s %5d s' $$step $$(( $$(date +%s) - t0 )))\n"; \
	done; echo "=== done ($$(date +%T))"; \
	printf "stage times (make test, %d s in all):\n$$times" $$(( $$(date +%s) - t_all )); \
	if [ -n "$$failed" ]; then echo "make test: FAILED:$$failed"; exit 1; fi

test-release: dataset
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 1800

# The suites under AddressSanitizer + UndefinedBehaviorSanitizer (gcc).
test-asan: dataset
	cmake -S . -B $(ASAN_BUILD) $(SAN_CMAKE) -DPLANCHECK_SANITIZE=ON
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	cd $(ASAN_BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 3600

# ThreadSanitizer (gcc) on the tests that exercise threads: by convention
# their names say so (TSAN_TESTS; tests/CMakeLists.txt). parallel_for runs on
# std::thread there (src/base/parallel.cpp says why); tests/tsan.supp lists what
# is suppressed. Only the files holding such tests are built, as one suite
# (plancheck_tsan_tests, tests/CMakeLists.txt), plus the API suite.
TSAN_TESTS ?= Thread|Concurren|^Parallel\.
TSAN_TARGETS ?= plancheck plancheck_api_tests plancheck_tsan_tests
test-tsan: dataset
	cmake -S . -B $(TSAN_BUILD) $(SAN_CMAKE) -DPLANCHECK_TSAN=ON
	cmake --build $(TSAN_BUILD) -j $(JOBS) --target $(TSAN_TARGETS)
	cd $(TSAN_BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 3600 -R '$(TSAN_TESTS)' --no-tests=error

fuzz-build: deps
	cmake -S . -B $(FUZZ_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DPLANCHECK_FUZZ=ON $(CMAKE_FLAGS)
	cmake --build $(FUZZ_BUILD) -j $(JOBS)

# Each libFuzzer target for FUZZ_SECONDS (model: FUZZ_MODEL_SECONDS, urdf:
# FUZZ_URDF_SECONDS) on a
# scratch copy of its seed corpus, JOBS targets at once (scripts/fuzz.sh).
fuzz: fuzz-build
	@scripts/fuzz.sh $(FUZZ_BUILD) $(JOBS) $(foreach t,$(FUZZ_TARGETS),$(t)=$(if $(filter model,$(t)),$(FUZZ_MODEL_SECONDS),$(if $(filter urdf,$(t)),$(FUZZ_URDF_SECONDS),$(FUZZ_SECONDS))))

# Micro benchmarks (each checks its answer first), then Table 3 beside FCL
# (answers checked state by state before anything is timed). Nothing else
# should run on the machine meanwhile: the numbers are wall-clock medians.
bench: dataset
	$(BUILD)/plancheck_bench --benchmark_min_time=0.2
	$(BUILD)/plancheck bench $(DATASET)/scene.json --fcl --fcl-repetitions 5 --repetitions 9 --json $(BUILD)/table3.json
	$(BUILD)/plancheck_regolith_bench $(DATASET)
	$(BUILD)/plancheck_continuous_bench $(DATASET)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(TSAN_BUILD) $(FUZZ_BUILD) $(DATASET)
