# contactmap: the two set-up commands are `make demo` and `make test`.
SHELL := /bin/bash
CARGO ?= cargo

# libhdf5 is compiled from source (hdf5-metno, feature "static"): it needs cmake.
CMAKE_DIR := $(shell scripts/ensure-cmake.sh)
ifneq ($(CMAKE_DIR),)
export PATH := $(CMAKE_DIR):$(PATH)
endif

BIN := target/release/contactmap

# The workspace but the criterion benches (benches/, a crate of its own): built together, the
# library, its tests, the binary and the Python module share one set of features, so contactmap
# is compiled once for all of them (and `maturin develop` / `make wheel` reuse it).
TESTED := --workspace --exclude contactmap-benches

.PHONY: all build web demo test test-venvs lint man check-peers bench clean python wheel

all: build

# --workspace: the crates compiled with the features the Python package needs too (numpy's
# num-complex, pyo3's syn), so that `make wheel` and `pip install ./python` reuse this build
# instead of compiling everything again
build:
	$(CARGO) build --release $(TESTED)

## make web: the viewer page of `contactmap serve` (web/: HiGlass, React and pixi.js bundled by
## vite) into web/dist, with the machine's npm from the committed lockfile; without npm it says so
web:
	scripts/build_web.sh

## make demo: build, then run the pipeline on the real example data shipped in data/
demo: build web
	CONTACTMAP=$(BIN) scripts/demo.sh

## make test: formatting, lints, docs and the whole test suite (what CI runs), then the Snakemake
## workflows on data/ (scripts/test_workflows.sh: installs the pinned snakemake in .venv-workflows)
# The Python module tested is the cdylib `cargo build --all-targets` makes beside the tests, with
# their dependencies (target/debug/lib_native.so; pyo3 told that it is an extension module, as
# maturin tells it): maturin's own build resolved the build scripts' dependencies apart from the
# tests' (no dev-dependencies) and compiled hdf5 and contactmap again (3.5 min on a fresh clone).
# The Python environments of the workflows' and the package's tests are installed while clippy
# compiles (pip mostly downloads and unpacks: a minute of a fresh clone's make test), and so is
# the viewer page (npm ci, vite build) that the browser test, last, opens in headless Chromium.
test: export PYO3_BUILD_EXTENSION_MODULE := 1
test:
	$(MAKE) --no-print-directory -j2 lint test-venvs
	$(CARGO) build $(TESTED) --all-targets
	$(CARGO) test $(TESTED) --all-targets
	$(CARGO) test $(TESTED) --doc
	RUSTDOCFLAGS="-D warnings" $(CARGO) doc --workspace --no-deps --quiet
	scripts/test_workflows.sh target/debug/contactmap
	scripts/test_python.sh target/debug/contactmap --module target/debug/lib_native.so
	scripts/test_browser.sh target/debug/contactmap

## make python: the Python package (python/) built with optimisations into .venv-python, tested
python: build
	scripts/test_python.sh $(BIN) --release

## make wheel: the Python package as one abi3 wheel in target/wheel, reusing `make build`'s
## compiled crates; `pip install target/wheel/contactmap-*.whl` anywhere (no compiler needed)
wheel: build
	scripts/build_wheel.sh

## make man: one man page per command into target/man (man -l target/man/contactmap-balance.1)
man: build
	$(BIN) man --dir target/man

test-venvs:
	scripts/test_workflows.sh --prepare
	scripts/test_python.sh --prepare
	scripts/build_web.sh --if-stale

lint:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

## make check-peers: open every file we write with cooler 0.11 (needs a venv: see docs/peers.md)
check-peers: build
	scripts/check_peers.sh

## make bench: side-by-side timings against the peer tools (see docs/performance.md); the
## criterion benches of our own functions are `cargo bench -p contactmap-benches`
bench: build
	scripts/bench_peers.sh

clean:
	$(CARGO) clean
