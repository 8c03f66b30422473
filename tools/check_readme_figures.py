#!/usr/bin/env python3
"""Checks that the figures the READMEs quote from the runs of the tasks still hold.

Each claim below names a README, the exact sentence fragment that quotes a figure, the task whose
run gives it and a check of the run's summary (the rows of report.html that `cobra run APP
--report DIR` writes). The script runs each task once, reads its summary and fails (exit 1,
naming the README, the fragment and what the run gave) when a fragment is no longer in its README
or its figure no longer holds. A README figure that is not a claim here (or in a test) is not
re-measured: quote none.

    tools/check_readme_figures.py --cobra build/release/tools/cobra/cobra [--root DIR]
"""
import argparse
import html
import os
import re
import subprocess
import sys
import tempfile


def summary_of(report_html):
    """The summary table of a report.html as {row name: value text}."""
    rows = re.findall(r"<tr><th>(.*?)</th><td>(.*?)</td></tr>", report_html)
    return {html.unescape(k): html.unescape(v) for k, v in rows}


def millimetres(text):
    """Every 'N mm' of `text` as floats [mm]."""
    return [float(v) for v in re.findall(r"(-?\d+(?:\.\d+)?) mm", text)]


def row(summary, prefix):
    """The value of the first row whose name starts with `prefix`; KeyError naming it if none."""
    for name, value in summary.items():
        if name.startswith(prefix):
            return value
    raise KeyError(f"no summary row '{prefix}...'")


def placement_about(figure_mm):
    def check(summary):
        values = millimetres(row(summary, "placement error per needle"))
        ok = bool(values) and all(round(v, 1) == figure_mm for v in values)
        return ok, f"placements {values} mm"
    return check


def worst_tracking_under(robot, limit_mm):
    def check(summary):
        worst = millimetres(row(summary, f"worst tracking, {robot}"))[0]
        return worst < limit_mm, f"worst tracking of {robot} {worst} mm"
    return check


def clearance_above_threshold(summary):
    text = row(summary, "worst clearance")
    worst = millimetres(text)[0]
    threshold = millimetres(next(k for k in summary if k.startswith("worst clearance")))[0]
    under = re.search(r"(\d+\.\d+) s at or under the threshold", text)
    ok = worst > threshold and under is not None and float(under.group(1)) == 0.0
    return ok, f"worst clearance {worst} mm against {threshold} mm ({text})"


def numbers(text):
    """Every number of `text`, as written."""
    return re.findall(r"-?\d+(?:\.\d+)?", text)


def as_quoted(value, quoted):
    """`value` written with as many decimals as `quoted`."""
    decimals = len(quoted.split(".")[1]) if "." in quoted else 0
    return f"{value:.{decimals}f}"


def figure(prefix, quoted, nth=0):
    """The summary row starting with `prefix`: its nth number, rounded as `quoted` is, is `quoted`."""
    def check(summary):
        value = row(summary, prefix)
        measured = as_quoted(float(numbers(value)[nth]), quoted)
        return measured == quoted, f"{prefix}: {measured} ({value})"
    return check


def figure_in_name(prefix, quoted):
    """The summary row starting with `prefix`: the first number of its name is `quoted`."""
    def check(summary):
        name = next(k for k in summary if k.startswith(prefix))
        measured = as_quoted(float(numbers(name)[0]), quoted)
        return measured == quoted, f"'{name}'"
    return check


def span(prefix, low, high, start, step=2):
    """Of the row's numbers start, start + step, ...: the smallest is `low`, the largest `high`."""
    def check(summary):
        value = row(summary, prefix)
        picked = [float(v) for v in numbers(value)[start::step]]
        measured = (as_quoted(min(picked), low), as_quoted(max(picked), high))
        return measured == (low, high), f"{prefix}: {measured[0]}-{measured[1]} ({value})"
    return check


# (README, fragment quoting the figure, task, check of the task's summary)
CLAIMS = [
    ("README.md", "It simulates 163 s", "puncturing", figure("duration", "163")),
    ("README.md", "placement about 0.3 mm", "puncturing", placement_about(0.3)),
    ("README.md", "tracking under 0.5 mm for the needle and 1.2 mm for the probe", "puncturing",
     lambda s: all_of(s, worst_tracking_under("I-SUR needle", 0.5), worst_tracking_under("UR5 probe", 1.2))),
    ("README.md", "the clearance above its 5 mm threshold", "puncturing", clearance_above_threshold),
    ("README.md", "faults detected (0 on the nominal run", "puncturing", figure("faults detected", "0")),
    ("apps/suturing/README.md", "67.3 s simulated", "suturing", figure("duration", "67.3")),
    ("apps/suturing/README.md", "8 half-stitches, 4 stitches", "suturing",
     lambda s: all_of(s, figure("half-stitches applied", "8"), figure("stitches completed", "4"))),
    ("apps/suturing/README.md", "the widest gap along the cut at the end 1.39 mm", "suturing",
     figure("widest gap along the cut at the end", "1.39")),
    ("apps/suturing/README.md", "tension at the end of each pull 7.56-7.63 N after a right half", "suturing",
     span("thread tension at the end of each pull", "7.56", "7.63", 0)),
    ("apps/suturing/README.md", "3.55-4.55 N after a left half", "suturing",
     span("thread tension at the end of each pull", "3.55", "4.55", 1)),
    ("apps/suturing/README.md", "worst tracking 0.42 mm (Endo Stitch) and 0.30 mm (the stick's tip)", "suturing",
     lambda s: all_of(s, figure("worst tracking, Endo Stitch", "0.42"), figure("worst tracking, stick", "0.30"))),
    ("apps/suturing/README.md", "worst clearance 5.21 mm (threshold 4 mm)", "suturing",
     lambda s: all_of(s, figure("worst clearance", "5.21"), figure_in_name("worst clearance", "4"))),
]


def all_of(summary, *checks):
    results = [c(summary) for c in checks]
    return all(ok for ok, _ in results), "; ".join(why for _, why in results)


def check_claims(root, summaries, claims=CLAIMS):
    """The failures of `claims` (README text under `root`, run summaries by task) as messages."""
    failures = []
    for readme, fragment, task, check in claims:
        with open(os.path.join(root, readme), encoding="utf-8") as f:
            text = " ".join(f.read().split())  # a fragment may wrap over lines
        if fragment not in text:
            failures.append(f"{readme}: no longer quotes '{fragment}': update the claim in {__file__}")
            continue
        try:
            ok, measured = check(summaries[task])
        except (KeyError, IndexError, StopIteration) as error:
            ok, measured = False, f"the run of {task} has no such figure ({error})"
        if not ok:
            failures.append(f"{readme}: '{fragment}' no longer holds: the run of apps/{task} gave {measured}")
    return failures


def run_task(cobra, root, task, folder):
    out = subprocess.run([cobra, "run", os.path.join(root, "apps", task), "--report", folder, "--quiet"],
                         capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(f"cobra run apps/{task} failed ({out.returncode}): {out.stderr[-2000:]}")
    with open(os.path.join(folder, "report.html"), encoding="utf-8") as f:
        return summary_of(f.read())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cobra", required=True, help="the cobra tool (build/release/tools/cobra/cobra)")
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    args = parser.parse_args()
    summaries = {}
    with tempfile.TemporaryDirectory() as runs:
        for task in sorted({c[2] for c in CLAIMS}):
            summaries[task] = run_task(args.cobra, args.root, task, os.path.join(runs, task))
    failures = check_claims(args.root, summaries)
    for failure in failures:
        print(failure, file=sys.stderr)
    print(f"{len(CLAIMS) - len(failures)} of {len(CLAIMS)} README figures hold")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
