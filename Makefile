# SPDX-License-Identifier: MIT
# The README's two commands: `make demo` and `make test`. Each installs what is
# missing (scripts/install-deps.sh), builds, and (re)generates the default dataset.
BUILD  ?= build
JOBS   ?= $(shell nproc)
CMAKE_FLAGS ?=
DATASET := datasets/change5
GEN     := $(BUILD)/generate_change5

# Sanitizer and fuzz builds (README "Sanitizers and fuzzing"): each its own
# build folder, building only what its tests need (no benchmarks).
ASAN_BUILD ?= build-asan
TSAN_BUILD ?= build-tsan
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 60
# fuzz_model forks an importer child per input (src/isolate.h), about 60
# inputs a second under ASan against thousands for the others: it gets longer.
FUZZ_MODEL_SECONDS ?= 180
FUZZ_TARGETS ?= scene plan model dem verify
# -O2 as in Release, line tables only (-g1): readable reports, lighter builds.
SAN_CMAKE := -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
             -DPLANCHECK_BUILD_BENCH=OFF $(CMAKE_FLAGS)
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
# fails the whole.
test:
	@failed=; for step in test-release test-asan test-tsan fuzz; do \
	  echo "=== make $$step ($$(date +%T))"; $(MAKE) --no-print-directory $$step || failed="$$failed $$step"; \
	done; echo "=== done ($$(date +%T))"; \
	if [ -n "$$failed" ]; then echo "make test: FAILED:$$failed"; exit 1; fi

test-release: dataset
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 1800

# The suites under AddressSanitizer + UndefinedBehaviorSanitizer (gcc).
test-asan: dataset
	cmake -S . -B $(ASAN_BUILD) $(SAN_CMAKE) -DPLANCHECK_SANITIZE=ON
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	cd $(ASAN_BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 3600

# The suites under ThreadSanitizer (gcc); parallel_for runs on std::thread
# there (src/parallel.cpp says why); tests/tsan.supp lists what is suppressed.
test-tsan: dataset
	cmake -S . -B $(TSAN_BUILD) $(SAN_CMAKE) -DPLANCHECK_TSAN=ON
	cmake --build $(TSAN_BUILD) -j $(JOBS)
	cd $(TSAN_BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 3600

fuzz-build: deps
	cmake -S . -B $(FUZZ_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DPLANCHECK_FUZZ=ON $(CMAKE_FLAGS)
	cmake --build $(FUZZ_BUILD) -j $(JOBS)

# Each libFuzzer target for FUZZ_SECONDS (model: FUZZ_MODEL_SECONDS) on a scratch copy of its seed corpus
# (the committed corpus never grows by itself). Any crash, sanitizer report,
# exception other than InputError, broken invariant, input slower than 10 s or
# over 2 GB fails; the input that did it is kept under $(FUZZ_BUILD)/artifacts/.
fuzz: fuzz-build
	@mkdir -p $(FUZZ_BUILD)/artifacts; status=0; \
	for t in $(FUZZ_TARGETS); do \
	  work=$$(mktemp -d); cp -r tests/fuzz/corpus/$$t $$work/corpus; \
	  secs=$(FUZZ_SECONDS); [ $$t != model ] || secs=$(FUZZ_MODEL_SECONDS); \
	  echo "fuzz_$$t: $$secs s on a copy of tests/fuzz/corpus/$$t"; \
	  if $(FUZZ_BUILD)/fuzz/fuzz_$$t $$work/corpus -max_total_time=$$secs -timeout=10 \
	       -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix=$(CURDIR)/$(FUZZ_BUILD)/artifacts/$$t- \
	       > $(FUZZ_BUILD)/fuzz-$$t.log 2>&1; then \
	    echo "fuzz_$$t: ok, $$(grep -h 'stat::number_of_executed_units' $(FUZZ_BUILD)/fuzz-$$t.log | awk '{print $$2}') executions, corpus $$(ls $$work/corpus | wc -l) files"; \
	  else \
	    status=1; echo "fuzz_$$t: FAILED (log below, input in $(FUZZ_BUILD)/artifacts/)"; tail -n 60 $(FUZZ_BUILD)/fuzz-$$t.log; \
	  fi; \
	  rm -rf $$work; \
	done; exit $$status

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
