"""The study statistics against scipy: runs study_stats_dump (the library's figures for seeded random
inputs) and recomputes each with scipy.stats, to 1e-9 relative (1e-12 absolute near zero)."""
import itertools
import json
import math
import subprocess
import sys
import warnings

import numpy as np
from scipy import special, stats

REL, ABS = 1e-9, 1e-12
failures = []
counts = {}


def close(a, b, rel=REL, abs_=ABS):
    if a is None or b is None:
        return a is None and b is None
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return abs(a - b) <= max(abs_, rel * max(abs(a), abs(b)))


def check(case, what, ours, theirs, **tolerance):
    if not close(ours, theirs, **tolerance):
        failures.append(f"{case['test']} {what}: ours {ours!r}, scipy {theirs!r}; input "
                        f"{json.dumps({k: v for k, v in case.items() if k != 'test'})[:300]}")


def wilson(k, n):
    ci = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    return ci.low, ci.high


def exact_p_by_enumeration(d):
    """Two-sided exact p of W+ with average ranks (ties too), over every sign pattern."""
    ranks = stats.rankdata(np.abs(d))
    observed = ranks[d > 0].sum()
    sums = [sum(r for r, s in zip(ranks, signs) if s)
            for signs in itertools.product([False, True], repeat=len(d))]
    below = sum(1 for s in sums if s <= observed + 1e-9)
    above = sum(1 for s in sums if s >= observed - 1e-9)
    return min(1.0, 2 * min(below, above) / len(sums))


def main():
    warnings.filterwarnings("ignore")  # scipy's notes on small samples: compared all the same
    out = subprocess.run([sys.argv[1]], check=True, capture_output=True, text=True).stdout
    for line in out.splitlines():
        case = json.loads(line)
        kind = case["test"]
        counts[kind] = counts.get(kind, 0) + 1
        if kind == "wilson":
            lo, hi = wilson(case["k"], case["n"])
            check(case, "lo", case["lo"], lo)
            check(case, "hi", case["hi"], hi)
        elif kind == "combined":
            p1, p2 = case["k1"] / case["n1"], case["k2"] / case["n2"]
            if p1 <= p2:
                upper, lower = wilson(case["k1"], case["n1"])[1], wilson(case["k2"], case["n2"])[0]
            else:
                upper, lower = wilson(case["k2"], case["n2"])[1], wilson(case["k1"], case["n1"])[0]
            combined = math.hypot(min(p1, p2) - upper, max(p1, p2) - lower)
            check(case, "combined", case["combined"], combined)
            check(case, "difference", case["difference"], p2 - p1)
            if case["significant"] != (abs(p2 - p1) > combined):
                failures.append(f"combined verdict differs: {case}")
        elif kind == "wilcoxon":
            x1, x2 = np.array(case["first"]), np.array(case["second"])
            d = x2 - x1
            nz = d[d != 0]
            if case["n"] != len(nz):
                failures.append(f"wilcoxon n: ours {case['n']}, non-zero pairs {len(nz)}")
            if len(nz) == 0:
                continue
            approx = stats.wilcoxon(x2, x1, zero_method="wilcox", correction=False,
                                    method="approx")
            check(case, "T", case["t"], approx.statistic)
            check(case, "z", -abs(case["z"]), approx.zstatistic)
            ranks = stats.rankdata(np.abs(nz))
            check(case, "W+", case["w_plus"], ranks[nz > 0].sum())
            check(case, "W", case["w"], abs(ranks[nz > 0].sum() - ranks[nz < 0].sum()))
            ties = len(np.unique(np.abs(nz))) < len(nz)
            if not case["exact"]:
                check(case, "p (normal)", case["p"], approx.pvalue)
            elif not ties:
                exact = stats.wilcoxon(nz, method="exact")  # zeros dropped: scipy's exact needs none
                check(case, "p (exact)", case["p"], exact.pvalue)
            elif len(nz) <= 14:
                check(case, "p (exact, ties)", case["p"], exact_p_by_enumeration(nz))
        elif kind == "critical":
            n, t = case["n"], case["critical_t"]
            # T = t from n untied differences: ranks summing to t negative, the rest positive.
            def p_of(t_value):
                negative, left = set(), t_value
                for r in range(n, 0, -1):
                    if r <= left:
                        negative.add(r)
                        left -= r
                d = [-r if r in negative else r for r in range(1, n + 1)]
                return stats.wilcoxon(d, method="exact").pvalue
            if t >= 0 and not p_of(t) <= 0.05:
                failures.append(f"critical T {t} for n = {n}: scipy's exact p {p_of(t)} > 0.05")
            if t + 1 <= n * (n + 1) // 4 and not p_of(t + 1) > 0.05:
                failures.append(f"critical T {t} for n = {n}: T = {t + 1} is significant too")
        elif kind == "ttest":
            x1, x2 = np.array(case["first"]), np.array(case["second"])
            rel = stats.ttest_rel(np.array(case["paired_second"]), x1)
            check(case, "paired t", case["paired"]["t"], rel.statistic)
            check(case, "paired p", case["paired"]["p"], rel.pvalue)
            welch = stats.ttest_ind(x2, x1, equal_var=False)
            check(case, "welch t", case["welch"]["t"], welch.statistic)
            check(case, "welch p", case["welch"]["p"], welch.pvalue)
            v1, v2 = x1.var(ddof=1) / len(x1), x2.var(ddof=1) / len(x2)
            df = (v1 + v2) ** 2 / (v1 ** 2 / (len(x1) - 1) + v2 ** 2 / (len(x2) - 1))
            check(case, "welch df", case["welch"]["df"], df)
        elif kind == "beta":
            check(case, "I_x(a, b)", case["value"], special.betainc(case["a"], case["b"], case["x"]),
                  rel=1e-9, abs_=1e-300)
    smallest = min((json.loads(l)["welch"]["p"] for l in out.splitlines()
                    if json.loads(l)["test"] == "ttest"), default=1)
    print("compared with scipy:", ", ".join(f"{k} {v}" for k, v in counts.items()),
          f"(smallest Welch p {smallest:.3g})")
    for f in failures[:20]:
        print("FAIL", f)
    if failures:
        print(f"{len(failures)} differences")
        sys.exit(1)


main()
