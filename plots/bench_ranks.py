"""bench_ranks.py: the tables and charts of ./run.sh bench-ranks (plots/bench_ranks.sh).

Reads OUT/scaling.txt (one row per run on ranks), writes OUT/projection.txt and the charts
OUT/ranks_memory.png (peak memory per rank against the unknowns per rank, each path; the
one-process runs beside) and OUT/ranks_projection.png (the fitted model's memory per rank
and time per step at 1e7 and 1e8 unknowns against the ranks).

The model, fitted by least squares on the rows of each path (its assumptions are printed in
projection.txt):
  peak memory per rank (MB) = a + b n + c n^e / N (+ d nc^2 on the direct path)
    n the unknowns, N the ranks; b n is what every rank holds whole (the mesh, vectors of n),
    c n^e / N what is divided (the rows of M, A, B, R'SR and the Newton matrix, and the
    factor or the AMG hierarchy: e = 1.4 for MUMPS, the fill measured on one process from 92k
    to 212k unknowns; e = 1 for BoomerAMG); the direct path's rank 0 also holds the kernel's
    dense contact-size matrices (Dw, N0 and its inverse: d = 24 bytes, not fitted), nc the
    contact slots, about 3 (nx + 1)(ny + 1) on the slab nx = 2 ny = 2 nz of n unknowns;
  time per step (s) = t0 (n / n0)^f / N
    t0, n0 and f from the runs with N <= cores (on more ranks than cores the ranks share them: those
    times are not scaling), f from the one-rank runs of two sizes; perfect strong scaling
    beyond, an optimistic assumption (the direct path's Newton runs on rank 0 alone: its
    time is not divided by N).
Usage: bench_ranks.py OUT
"""
import os
import sys

import numpy as np


def read_rows(path):
    names, rows = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                names = line[1:].split()
                continue
            words = line.split()
            if words:
                rows.append(dict(zip(names, words)))
    return rows


def number(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError):
        return float("nan")


def slots(n):
    """The contact slots of the slab nx = 2 ny = 2 nz with n = 3 (nx+1)(ny+1)(nz+1) unknowns."""
    low, high = 0.0, 2 * (4 * n / 3) ** (1 / 3)
    for _ in range(100):               # (nx + 1)(nx/2 + 1)^2 = n/3, by bisection
        nx = 0.5 * (low + high)
        low, high = (nx, high) if (nx + 1) * (nx / 2 + 1) ** 2 < n / 3 else (low, nx)
    return 3 * (nx + 1) * (nx / 2 + 1)


DENSE_MB = 24e-6                      # rank 0, direct path: MB per nc^2 (Dw, N0, its inverse)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: bench_ranks.py OUT")
    out = sys.argv[1]
    rows = read_rows(os.path.join(out, "scaling.txt"))
    cores = os.cpu_count() or 1
    exponents = {"direct": 1.4, "iterative": 1.0}
    lines = ["# projection of -ranks N (plots/bench_ranks.py): memory per rank = a + b n + c n^e / N (MB; direct: + 24e-6 nc^2 on rank 0, nc the slab's contact slots),"
             " time per step = t0 (n/n0)^f / N (direct: / 1, its Newton on rank 0), t0, n0, f from the runs on at most as many ranks as cores",
             f"# {len(rows)} runs in {out}/scaling.txt; cores {cores}",
             "# path quantity value"]
    fits = {}

    def model_memory(path, coef, e, target, ranks):
        dense = DENSE_MB * slots(target) ** 2 if path == "direct" else 0
        return coef[0] + coef[1] * target + coef[2] * target ** e / ranks + dense

    for path, e in exponents.items():
        sel = [r for r in rows if r["path"] == path and np.isfinite(number(r, "memory_peak_rank_mb_max"))]
        if len(sel) < 3:
            lines.append(f"# {path}: not fitted, {len(sel)} runs (the model has 3 coefficients: ./run.sh bench-ranks without --quick)")
            continue
        n = np.array([number(r, "unknowns") for r in sel])
        N = np.array([number(r, "ranks") for r in sel])
        mem = np.array([number(r, "memory_peak_rank_mb_max") for r in sel])
        dense = DENSE_MB * np.array([slots(x) for x in n]) ** 2 if path == "direct" else 0 * n
        A = np.column_stack([np.ones_like(n), n, n ** e / N])
        coef, *_ = np.linalg.lstsq(A, mem - dense, rcond=None)
        coef = np.maximum(coef, 0)
        timed = [r for r in sel if number(r, "ranks") <= cores and np.isfinite(number(r, "step_s"))]
        ones = sorted([r for r in timed if number(r, "ranks") == 1], key=lambda r: number(r, "unknowns"))
        f = 1.0
        if len(ones) >= 2 and number(ones[-1], "unknowns") > number(ones[0], "unknowns"):
            f = np.log(number(ones[-1], "step_s") / number(ones[0], "step_s")) / np.log(number(ones[-1], "unknowns") / number(ones[0], "unknowns"))
        ref = ones[-1] if ones else (timed[-1] if timed else None)
        t0 = number(ref, "step_s") if ref else float("nan")
        n0 = number(ref, "unknowns") if ref else float("nan")
        fits[path] = (coef, e, t0, n0, f)
        lines += [f"{path} a_mb {coef[0]:.4g}", f"{path} b_mb_per_unknown {coef[1]:.4g}", f"{path} c_mb {coef[2]:.4g}",
                  f"{path} exponent_e {e}", f"{path} time_t0_s {t0:.4g}", f"{path} time_n0 {n0:.0f}", f"{path} time_exponent_f {f:.3g}"]
        for target in (1e7, 1e8):
            for ranks in (16, 64, 256, 1024, 4096):
                m = model_memory(path, coef, e, target, ranks)
                t = t0 * (target / n0) ** f / (1 if path == "direct" else ranks)
                lines.append(f"{path} n {target:.0e} ranks {ranks} memory_per_rank_mb {m:.4g} time_per_step_s {t:.4g}")
    with open(os.path.join(out, "projection.txt"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for path, marker in (("direct", "o"), ("iterative", "s")):
        sel = [r for r in rows if r["path"] == path]
        if sel:
            x = [number(r, "unknowns") / number(r, "ranks") for r in sel]
            ax.scatter(x, [number(r, "memory_peak_rank_mb_max") for r in sel], marker=marker, label=f"-ranksolver {path} (largest rank)")
    one = {r["unknowns"]: number(r, "one_process_memory_mb") for r in rows if np.isfinite(number(r, "one_process_memory_mb"))}
    if one:
        ax.scatter([float(k) for k in one], list(one.values()), marker="x", color="k", label="one process")
    ax.set_xscale("log"); ax.set_yscale("log")
    ax.set_xlabel("unknowns per rank"); ax.set_ylabel("peak memory per rank (MB)")
    ax.set_title("slab3d, 2 steps: memory per rank")
    ax.legend(fontsize=8)
    fig.tight_layout(); fig.savefig(os.path.join(out, "ranks_memory.png"), dpi=110); plt.close(fig)
    if not fits and os.path.exists(os.path.join(out, "ranks_projection.png")):
        os.remove(os.path.join(out, "ranks_projection.png"))   # (an older fit's chart would not match projection.txt)
    if fits:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
        ranks = np.array([4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096], dtype=float)
        for path, (coef, e, t0, n0, f) in fits.items():
            for target, style in ((1e7, "-"), (1e8, "--")):
                axes[0].plot(ranks, model_memory(path, coef, e, target, ranks) / 1024, style, label=f"{path}, n = {target:.0e}")
                axes[1].plot(ranks, t0 * (target / n0) ** f / (np.ones_like(ranks) if path == "direct" else ranks), style, label=f"{path}, n = {target:.0e}")
        for a, label in ((axes[0], "memory per rank (GB)"), (axes[1], "time per step (s)")):
            a.set_xscale("log"); a.set_yscale("log"); a.set_xlabel("ranks"); a.set_ylabel(label); a.legend(fontsize=7)
        axes[0].axhline(24, color="gray", lw=0.8)
        axes[0].set_title("largest rank: the whole mesh, and on the direct\npath rank 0's dense contact matrices, set a floor", fontsize=10)
        axes[1].set_title("time per step: iterative, perfect strong scaling\nassumed; direct, the Newton on rank 0 alone", fontsize=10)
        fig.tight_layout(); fig.savefig(os.path.join(out, "ranks_projection.png"), dpi=110); plt.close(fig)


if __name__ == "__main__":
    main()
