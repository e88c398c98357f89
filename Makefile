# Thin wrapper: each target installs missing Debian packages, configures (Release) and builds.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
DEMO_OUT ?= demo_output
SKELGRASP := $(BUILD_DIR)/apps/skelgrasp

.PHONY: all deps configure build test demo bench format clean

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) > /dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

demo: build
	@$(SKELGRASP) demo --out $(DEMO_OUT)

bench: build
	@$(SKELGRASP) bench skeleton --help > /dev/null && echo "see README: Benchmarks"

format:
	@find common perception reconstruction skeleton grasping evaluation datasets apps tests bench \
	  \( -name '*.h' -o -name '*.cpp' \) 2>/dev/null | xargs -r clang-format -i

clean:
	@rm -rf $(BUILD_DIR)
