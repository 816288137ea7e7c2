"""The Python call's overhead over the Rust call, for one dent on a 25,000-triangle target.

    python integrations/python/bench/overhead.py --json docs/bench/python_overhead_vm.json

The Rust call is what dentbend.dent runs once the arrays are read: the two meshes made from
them and the dent (timed inside Rust, with no Python object involved). The Python call is
dentbend.dent itself: arrays checked and read, the interpreter lock released and taken back,
the results made into numpy arrays. Both run in the same process, in alternating rounds, and
the medians are compared.
"""

import argparse
import json
import os
import platform
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))

import dentbend  # noqa: E402
from dentbend import _dentbend  # noqa: E402
import meshes  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", help="write the figures to this file")
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--per-round", type=int, default=5)
    args = parser.parse_args()

    # A 2 m ball of 100 rings x 126 segments (24,948 triangles), hit by a 0.3 m ball.
    target = meshes.sphere(1.0, rings=100, segments=126)
    ball = meshes.sphere(0.3, rings=16, segments=32, center=(0.0, 0.0, 1.3))
    arguments = (*target, *ball, (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (0.0, 0.0, -3.0), 0.05)
    dentbend.dent(*arguments)  # warm up

    python_times, rust_times = [], []
    for _ in range(args.rounds):
        for _ in range(args.per_round):
            start = time.perf_counter()
            dentbend.dent(*arguments)
            python_times.append(time.perf_counter() - start)
        rust_times.append(_dentbend.rust_dent_seconds(arguments, args.per_round))
    python_median = statistics.median(python_times)
    rust_median = statistics.median(rust_times)
    figures = {
        "target_triangles": int(len(target[1])),
        "target_vertices": int(len(target[0])),
        "projectile_triangles": int(len(ball[1])),
        "python_median_s": python_median,
        "rust_median_s": rust_median,
        "overhead": python_median / rust_median - 1.0,
        "python_runs": len(python_times),
        "rust_runs": args.rounds * args.per_round,
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs",
        "python": platform.python_version(),
        "numpy": np.__version__,
    }
    text = json.dumps(figures, indent=2)
    print(text)
    if args.json:
        with open(args.json, "w") as out:
            out.write(text + "\n")


if __name__ == "__main__":
    main()
