#!/usr/bin/env bash
# The project's test command (README "The two commands"). On a fresh machine
# it installs what it needs: the Rust crates (cargo fetches them) and a Python
# venv with FMPy, pythonfmu, pytest and MkDocs from PyPI. Then: the docs book,
# formatting, clippy, building the FMUs, every Rust test, the leak check of the
# export layer, and the Python (FMPy) tests.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
step() { printf '\n=== %s (%d s since start) ===\n' "$*" "$SECONDS"; }

step "Python venv with FMPy, cargo-zigbuild and zig"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/python/requirements.txt -r docs/requirements.txt
export PATH="$root/.venv/bin:$PATH"

step "toolchains of the FMU platforms (win64: mingw-w64, wine for the test) and libclang (rust-fmi's fmi-sys)"
rustup target add x86_64-pc-windows-gnu
if ! command -v x86_64-w64-mingw32-gcc >/dev/null || [ ! -x /usr/lib/wine/wine64 ] \
    || ! ls /usr/lib/llvm-*/lib/libclang.so >/dev/null 2>&1; then
    sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    # libclang-dev: the `fmi` crate's bindings (fmi-sys, bindgen) for tests/tests/rust_fmi.rs
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
        gcc-mingw-w64-x86-64 binutils-mingw-w64-x86-64 wine64 libclang-dev >/dev/null
fi
# every platform must be built and checked: a missing toolchain fails instead of skipping
export FMU_PLATFORMS=linux64-portable,win64

step "docs book (mkdocs build --strict: broken links and anchors fail; site in target/book)"
.venv/bin/python -m mkdocs build --strict -f docs/mkdocs.yml  # not --quiet: it hides the warnings that --strict counts

step "cargo fmt --check"
cargo fmt --all --check

step "cargo clippy"
cargo clippy --workspace --all-targets --release -- -D warnings

step "build the FMUs (target/fmu)"
cargo run --release -p packaging

step "cargo test"
cargo test --workspace --release

# The wheel compiles in the background while the single-threaded steps below (valgrind, the
# FMPy tests) run, so the second core is not idle; its log is printed when it is needed.
cargo build --release -p fmi-master -p chatter --bins
rm -rf target/wheels
(cd python && exec maturin build --profile fmu-release --zig --compatibility manylinux2014 \
    -i "$root/.venv/bin/python" -o "$root/target/wheels") > target/wheel-build.log 2>&1 &
wheel_pid=$!
trap 'kill "$wheel_pid" 2>/dev/null || true' EXIT # a failing step below stops the build too

step "leak check of the export layer (valgrind)"
if command -v valgrind >/dev/null; then
    bin=$(cargo test --release -p fmi2-export --test c_api --no-run --message-format=json 2>/dev/null \
        | .venv/bin/python -c 'import json,sys
for l in sys.stdin:
    m=json.loads(l)
    if m.get("reason")=="compiler-artifact" and m.get("executable") and m["target"]["name"]=="c_api": print(m["executable"])')
    valgrind --quiet --leak-check=full --errors-for-leak-kinds=definite --error-exitcode=1 \
        "$bin" --test-threads=1 2>&1 | tail -n 5
    echo "valgrind: no definite leaks, no memory errors"
else
    echo "valgrind not installed: leak check FAILED to run" >&2
    exit 1
fi

step "leak check of every product through its C ABI (valgrind, packaging/tests/conformance.rs)"
bin=$(cargo test --release -p packaging --test conformance --no-run --message-format=json 2>/dev/null \
    | .venv/bin/python -c 'import json,sys
for l in sys.stdin:
    m=json.loads(l)
    if m.get("reason")=="compiler-artifact" and m.get("executable") and m["target"]["name"]=="conformance": print(m["executable"])')
valgrind --quiet --suppressions=tests/valgrind.supp --leak-check=full --errors-for-leak-kinds=definite \
    --error-exitcode=1 "$bin" --test-threads=1 2>&1 | tail -n 5
echo "valgrind: every product's hostile-call table without definite leaks or memory errors"

step "Python tests (FMPy)"
FMU_DIR="$root/target/fmu" .venv/bin/python -m pytest -q tests/python

step "Python package chatter_fmu: abi3 wheel for glibc 2.17 (maturin + zig), installed into a fresh venv"
if ! wait "$wheel_pid"; then
    cat target/wheel-build.log >&2
    echo "building the wheel FAILED (log above)" >&2
    exit 1
fi
trap - EXIT
tail -n 2 target/wheel-build.log
python3 -m venv --clear target/wheel-venv
target/wheel-venv/bin/python -m pip install --quiet --disable-pip-version-check target/wheels/chatter_fmu-*.whl -r python/tests/requirements.txt
FMU_DIR="$root/target/fmu" target/wheel-venv/bin/python -m pytest -q python/tests
echo "all tests passed in $SECONDS s"
