# contactmap: the two set-up commands are `make demo` and `make test`.
SHELL := /bin/bash
CARGO ?= cargo

# libhdf5 is compiled from source (hdf5-metno, feature "static"): it needs cmake.
CMAKE_DIR := $(shell scripts/ensure-cmake.sh)
ifneq ($(CMAKE_DIR),)
export PATH := $(CMAKE_DIR):$(PATH)
endif

# Cargo caches rustc's target-information probe in target/.rustc_info.json; on fresh clones that
# cache has been seen holding a failed probe (rustc fed other processes' diagnostics), which then
# failed every later cargo command. Probing afresh costs milliseconds.
export CARGO_CACHE_RUSTC_INFO := 0

BIN := target/release/contactmap

.PHONY: all build demo test lint check-peers bench clean

all: build

build:
	$(CARGO) build --release < /dev/null

## make demo: build, then run the pipeline on the real example data shipped in data/
demo: build
	CONTACTMAP=$(BIN) scripts/demo.sh

## make test: formatting, lints, docs and the whole test suite (what CI runs)
## (standard input is /dev/null for every build step: rustc probes in build scripts read stdin)
test: lint
	$(CARGO) test --all-targets < /dev/null
	$(CARGO) test --doc < /dev/null
	RUSTDOCFLAGS="-D warnings" $(CARGO) doc --no-deps --quiet < /dev/null

lint:
	$(CARGO) fmt --all -- --check < /dev/null
	$(CARGO) clippy --all-targets -- -D warnings < /dev/null

## make check-peers: open every file we write with cooler 0.11 (needs a venv: see docs/peers.md)
check-peers: build
	scripts/check_peers.sh

## make bench: side-by-side timings against the peer tools (see docs/performance.md)
bench: build
	scripts/bench_peers.sh

clean:
	$(CARGO) clean
