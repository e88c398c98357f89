# Thin wrapper: each target installs missing Debian packages, configures (Release) and builds.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo_output
SKELGRASP := $(BUILD_DIR)/apps/skelgrasp
# ccache (when installed) rewrites paths below the checkout to relative ones, so a fresh clone in
# another folder reuses the cache of an earlier one.
export CCACHE_BASEDIR ?= $(CURDIR)

SANITIZE_DIR ?= $(BUILD_DIR)-sanitize
FUZZ_DIR ?= $(BUILD_DIR)-fuzz
# `make fuzz SECONDS=N`: how long each fuzz target runs.
SECONDS ?= 60
# Sanitizer run-time options: stop at the first finding; suppressions for third-party code only.
SANITIZER_ENV := ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:strict_string_checks=1 \
  LSAN_OPTIONS=suppressions=$(CURDIR)/scripts/sanitizers/lsan.supp:print_suppressions=0 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=$(CURDIR)/scripts/sanitizers/ubsan.supp

.PHONY: all deps configure build test demo bench sanitize fuzz format clean

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) > /dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	@scripts/install-deps.sh --test
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# The demo needs only the `skelgrasp` target: the launcher and the two command programs it starts
# (apps/CMakeLists.txt). The tests, benchmarks and the Python module are left to `make test`.
demo: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target skelgrasp
	@$(SKELGRASP) demo --out $(DEMO_OUT)

# AddressSanitizer + UndefinedBehaviorSanitizer build of everything, then the test suite under it
# (SANITIZE_TESTS=regex over test names, SANITIZE_LABELS=regex over suites run a subset,
# SANITIZE_EXCLUDE=regex over test names leaves tests out;
# SANITIZE_TARGETS="skelgrasp common_tests ..." builds only those).
# docs/reliability.md.
sanitize: deps
	@cmake -S . -B $(SANITIZE_DIR) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSKELGRASP_SANITIZE=ON \
	  -DSKELGRASP_BUILD_BENCHMARKS=OFF > /dev/null
	@$(SANITIZER_ENV) cmake --build $(SANITIZE_DIR) -j $(JOBS) \
	  $(if $(SANITIZE_TARGETS),--target $(SANITIZE_TARGETS),)
	@cd $(SANITIZE_DIR) && $(SANITIZER_ENV) ctest --output-on-failure -j $(JOBS) \
	  $(if $(SANITIZE_TESTS),-R '$(SANITIZE_TESTS)',) $(if $(SANITIZE_LABELS),-L '$(SANITIZE_LABELS)',) \
	  $(if $(SANITIZE_EXCLUDE),-E '$(SANITIZE_EXCLUDE)',)

# libFuzzer targets of the readers (clang), each run for SECONDS; findings land in $(FUZZ_DIR)/findings.
fuzz:
	@scripts/install-deps.sh --fuzz
	@cmake -S . -B $(FUZZ_DIR) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
	  -DCMAKE_CXX_COMPILER=clang++ -DSKELGRASP_FUZZ=ON -DSKELGRASP_BUILD_TESTS=OFF \
	  -DSKELGRASP_BUILD_BENCHMARKS=OFF > /dev/null
	@cmake --build $(FUZZ_DIR) -j $(JOBS) --target fuzz_all
	@$(SANITIZER_ENV) scripts/fuzz.sh $(FUZZ_DIR) $(SECONDS) $(JOBS)

bench: build
	@$(SKELGRASP) bench skeleton --help > /dev/null && echo "see README: Benchmarks"

format:
	@find common geometry perception reconstruction skeleton grasping ranking presentation pipeline evaluation datasets apps tests bench fuzz python \
	  \( -name '*.h' -o -name '*.cpp' \) 2>/dev/null | xargs -r clang-format -i

clean:
	@rm -rf $(BUILD_DIR) $(SANITIZE_DIR) $(FUZZ_DIR)
