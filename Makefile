# The two commands: `make run` and `make test`. Everything else is a helper.
BUILD   ?= out/build
JOBS    ?= $(shell nproc)
CONFIG  ?= RelWithDebInfo
RECIPE  ?= configs/default.yaml
SYLVA    = $(BUILD)/app/sylva
CMAKE_ARGS ?=

.PHONY: all setup configure build run test check format-check bench clean
all: build

setup:
	@tools/setup.sh

$(BUILD)/build.ninja: CMakeLists.txt | setup
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=$(CONFIG) $(CMAKE_ARGS) >/dev/null

configure: setup $(BUILD)/build.ninja

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

run: build
	@$(SYLVA) build $(RECIPE)
	@$(SYLVA) lodcheck $(RECIPE) --no-images
	@$(SYLVA) verify $(RECIPE)

test: build
	@cd $(BUILD) && SYLVA_REQUIRE_GLTF_VALIDATOR=1 SYLVA_REQUIRE_CLIENTS=1 ctest --output-on-failure -j $(JOBS) --timeout 600

# The CI jobs beyond `make test` (.ci/run runs them all): sanitizers + fuzzers (.ci/sanitize.sh, its own clang
# build in out/build-san), the formatting check and the size budget (tools/size_budget.py: no new function over
# 120 lines or file over 800 beyond tools/size-allowlist.txt, which only shrinks).
check: setup
	@.ci/sanitize.sh
	@tools/format-check
	@tools/size_budget.py check

format-check:
	@tools/format-check

bench: build
	@tools/bench.sh $(BUILD)

clean:
	rm -rf out/build out/build-san out/fuzz-artifacts
