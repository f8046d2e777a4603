# Signorini: the two commands of the README quick start, and a few helpers.
#   make run   installs what is missing, builds (Release) and solves the default example
#   make test  installs what is missing, builds and runs the test suite (label `long` excluded)
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
EXAMPLE ?= examples/hertz_cylinder/hertz_cylinder.yaml
CMAKE_FLAGS ?=
# Debian's Python (numpy, matplotlib, yaml from install-deps), not another one first on PATH.
PYTHON ?= $(shell test -x /usr/bin/python3 && echo /usr/bin/python3 || echo python3)

.PHONY: deps configure build run test test-long bench report clean

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

run: build
	@$(BUILD_DIR)/signorini run $(EXAMPLE) -o results/$(notdir $(basename $(EXAMPLE)))

test: build
	@cd $(BUILD_DIR) && ctest -LE long --output-on-failure -j $(JOBS)

test-long: build
	@cd $(BUILD_DIR) && ctest -L long --output-on-failure

bench: build
	@$(BUILD_DIR)/bench/bench_elasticity --type hex8 --dofs 1000000
	@$(BUILD_DIR)/bench/bench_elasticity --type tet10 --dofs 1000000

# Every example run, then one HTML page of checks and plots: results/report/index.html.
report: build
	@$(PYTHON) scripts/report.py --build $(BUILD_DIR) --out results/report

clean:
	rm -rf $(BUILD_DIR)
