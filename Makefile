# Hemirad entry points: `make demo`, `make test`, `make bench` (each installs missing packages first).
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

FUZZ_SECONDS ?= 600
# ccache where it is installed (install-deps.sh installs it). The builds without OpenGL and without
# Embree compile most files exactly as the main build does, and ccache hands those objects over instead
# of compiling them again. Resolved when a recipe runs, that is after `deps`.
LAUNCHER = $(if $(shell command -v ccache 2>/dev/null),-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# The sanitizer build: -O1 and line tables only (-g1, enough for the reports' file:line) compile in
# half the time of RelWithDebInfo's -O2 -g, which matters more on 2 cores than the suite's run time.
SANITIZE_FLAGS = -O1 -g1 -DNDEBUG
SANITIZE_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1 \
	LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitizers.supp:print_suppressions=0 \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

.PHONY: all deps build python demo test bench test-sanitize test-without-opengl test-without-embree fuzz clean

all: build

deps:
	@bash scripts/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) $(LAUNCHER) > $(BUILD).configure.log 2>&1 || { cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD) -j $(JOBS)

# The Python module in $(BUILD)/python (PYTHONPATH=$(BUILD)/python python3 -c 'import hemirad').
python: build
	@cmake --build $(BUILD) --target python -j $(JOBS)

# The main job on the bundled Cornell box: F (hemisphere), solve, render out/cornell.png, timing table.
# F is the default one, the analytic estimator's (exact Lambert factors, reciprocal to rounding: the
# report's reciprocity max is 0); its row sums start at 0 because the floor runs under the blocks,
# and the 103 floor patches there see only the blocks' insides.
demo: build
	@mkdir -p out
	./$(BUILD)/hemirad render scenes/cornell_box.obj -o out/cornell.png --subdivide 20 --size 640x640

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	@bash bench/run.sh $(BUILD)

# The whole suite under AddressSanitizer + UndefinedBehaviorSanitizer (gcc), in build-sanitize/; without
# MPI (Open MPI's own allocations at exit would read as leaks in every rank) and without the Python
# module (an instrumented extension cannot load into an uninstrumented python3).
test-sanitize: deps
	@cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$(SANITIZE_FLAGS)" \
	    -DCMAKE_C_FLAGS_RELWITHDEBINFO="$(SANITIZE_FLAGS)" -DHEMIRAD_WITH_SANITIZERS=ON -DHEMIRAD_WITH_MPI=OFF -DHEMIRAD_WITH_PYTHON=OFF \
	    -DHEMIRAD_WITH_BENCH=OFF > build-sanitize.configure.log 2>&1 || { cat build-sanitize.configure.log; exit 1; }
	@cmake --build build-sanitize -j $(JOBS)
	@cd build-sanitize && $(SANITIZE_ENV) ctest --output-on-failure -j $(JOBS)

# The build without the optional components (CMake feature options): no OpenGL (no hemicube, no GUI)
# and no MPI/PETSc; the suite runs, --method hemicube says how to get it, and hemirad under mpirun
# runs one independent process per rank.
test-without-opengl: deps
	@cmake -S . -B build-noopengl $(LAUNCHER) -DCMAKE_BUILD_TYPE=Release -DHEMIRAD_WITH_OPENGL=OFF -DHEMIRAD_WITH_MPI=OFF -DHEMIRAD_WITH_BENCH=OFF \
	    > build-noopengl.configure.log 2>&1 || { cat build-noopengl.configure.log; exit 1; }
	@cmake --build build-noopengl -j $(JOBS)
	@cd build-noopengl && ctest --output-on-failure -j $(JOBS)

# The build without Embree (no hemisphere back end, no render): the hemicube is the default back end,
# the GUI is built without its ray-cast inspector, and whatever needs rays says how to get it. Position-
# independent code as in the main build (whose Python module needs it), so that ccache serves the
# objects both compile alike.
test-without-embree: deps
	@cmake -S . -B build-noembree $(LAUNCHER) -DCMAKE_POSITION_INDEPENDENT_CODE=ON -DCMAKE_BUILD_TYPE=Release -DHEMIRAD_WITH_EMBREE=OFF -DHEMIRAD_WITH_MPI=OFF -DHEMIRAD_WITH_PYTHON=OFF \
	    -DHEMIRAD_WITH_BENCH=OFF > build-noembree.configure.log 2>&1 || { cat build-noembree.configure.log; exit 1; }
	@cmake --build build-noembree -j $(JOBS)
	@cd build-noembree && ctest --output-on-failure -j $(JOBS)

# libFuzzer on the OBJ/MTL and F readers (clang), FUZZ_SECONDS per harness; corpus in build-fuzz/.
fuzz:
	@bash scripts/install-deps.sh fuzz
	@CC=clang CXX=clang++ cmake -S . -B build-fuzz -DHEMIRAD_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	    > build-fuzz.configure.log 2>&1 || { cat build-fuzz.configure.log; exit 1; }
	@cmake --build build-fuzz -j $(JOBS)
	@bash tests/fuzz/run.sh build-fuzz $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD) $(BUILD).configure.log build-sanitize build-sanitize.configure.log build-fuzz build-fuzz.configure.log \
	    build-noopengl build-noopengl.configure.log out
