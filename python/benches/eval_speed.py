"""ns per point of a vectorised `Table.eval` over 10⁶ points, against the Rust loop of
`crates/zoo/examples/lookup_loop.rs` over the same points (docs/performance.md, "From Python").

Bakes the default table at η = 1.33 as lookup_loop does, draws its 4,096 points the same way
(SplitMix64 from seed 1, ρ′ ∈ [0.05, 1), θ ∈ [0, 1.5), (r, φ) from the table's sampler) and
cycles through them to N points (default 10⁶), as its loop does. Then times, in alternation,
REPEAT times each (default 15): `Table.eval` (the call from Python: argument conversion, the
loop, the array back), and the package's `_loop_eval`, lookup_loop's loop of single
`TableRef::eval` calls over the same arrays, timed inside Rust, in the same process (what a
point of the runtime's batch call costs: the same single lookup per point). It does so once over
all N points, and block by block (BLOCK points, default 2¹⁶), summing each block's fastest
times. Prints the ns per point of each and their ratio: on a shared machine the paired minima,
and the blocks' above all, are the figures to trust.

Run: `python3 python/benches/eval_speed.py` after `python3 -m pip install ./python`; for a
second opinion, `N=4000000 cargo run --release -p bssrdf-zoo --example lookup_loop -- eval`.
"""

import os
import sys
import time

import numpy as np

import bssrdf_zoo as bz

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
from conftest import SplitMix64  # noqa: E402  (the command's random stream)


def lookup_points(table, rng):
    points = []
    while len(points) < 4096:
        rho, theta = 0.05 + 0.95 * rng.next_f64(), 1.5 * rng.next_f64()
        r, phi, pdf = table.sample(rho, theta, rng.next_f64(), rng.next_f64())
        if pdf > 0:
            points.append((rho, theta, r, phi))
    return np.array(points)


def paired(n, repeat, python_eval, rust_loop):
    """Fastest seconds of each of the two over `repeat` alternations."""
    python, rust = float("inf"), float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        python_eval()
        python = min(python, time.perf_counter() - start)
        rust = min(rust, rust_loop())
    return python / n * 1e9, rust / n * 1e9


def main():
    n = int(os.environ.get("N", 1_000_000))
    repeat = int(os.environ.get("REPEAT", 15))
    block = int(os.environ.get("BLOCK", 1 << 16))
    table = bz.bake(1.33).tables[0]
    points = lookup_points(table, SplitMix64(1))
    rho, theta, r, phi = (np.ascontiguousarray(np.resize(points[:, k], n)) for k in range(4))
    # The same lookups: the sums agree.
    s = table.eval(rho, theta, r, phi)
    total, _ = bz._native._loop_eval(table, rho, theta, r, phi)
    assert abs(total / s.sum() - 1) < 1e-12
    # One call over all n points, against the Rust loop over the same n points.
    whole = paired(
        n,
        repeat,
        lambda: table.eval(rho, theta, r, phi),
        lambda: bz._native._loop_eval(table, rho, theta, r, phi)[1],
    )
    # Calls of `block` points, each block timed `repeat` times in alternation with the Rust loop
    # over it and its fastest times summed: a load spike on a shared machine spoils one block's
    # round, not the figure.
    sums = [0.0, 0.0]
    for start in range(0, n, block):
        part = [a[start : start + block] for a in (rho, theta, r, phi)]
        m = len(part[0])
        py_ns, rust_ns = paired(m, repeat, lambda: table.eval(*part), lambda: bz._native._loop_eval(table, *part)[1])
        sums[0] += py_ns * m
        sums[1] += rust_ns * m
    blocks = (sums[0] / n, sums[1] / n)
    for name, (py_ns, rust_ns) in [(f"one call of {n} points", whole), (f"calls of {block} points", blocks)]:
        print(
            f"{name}: Table.eval from Python {py_ns:.1f} ns/point, Rust loop of single calls "
            f"{rust_ns:.1f} ns/point, ratio {py_ns / rust_ns:.2f} (fastest of {repeat})"
        )


if __name__ == "__main__":
    main()
