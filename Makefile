# Hemirad entry points: `make demo`, `make test`, `make bench` (each installs missing packages first).
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

.PHONY: all deps build demo test bench clean

all: build

deps:
	@bash scripts/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) > $(BUILD).configure.log 2>&1 || { cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD) -j $(JOBS)

# The main job on the bundled Cornell box: F (hemisphere), solve, render out/cornell.png, timing table.
demo: build
	@mkdir -p out
	./$(BUILD)/hemirad render scenes/cornell_box.obj -o out/cornell.png --subdivide 20 --samples 1024 --origins 4 --size 640x640

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	@bash bench/run.sh $(BUILD)

clean:
	rm -rf $(BUILD) $(BUILD).configure.log out
