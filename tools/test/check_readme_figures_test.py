#!/usr/bin/env python3
"""tools/check_readme_figures.py: a claim holds while its README quotes it and the run agrees; a
changed figure, a run that lost the row, or a README that no longer quotes the fragment fails,
naming the README and what the run gave."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import check_readme_figures as figures  # noqa: E402

REPORT = """<table>
<tr><th>duration</th><td>66.543 s</td></tr>
<tr><th>placement error per needle</th><td>0.26 mm, 0.27 mm (2 of 2)</td></tr>
<tr><th>thread tension at the end of each pull</th><td>7.63 N, 4.38 N, 7.60 N, 3.70 N</td></tr>
<tr><th>worst clearance (threshold 4.00 mm, allowed contacts apart)</th><td>5.21 mm at 10.641 s (a &amp; b); 0.000 s at or under the threshold of 66.5 s counted</td></tr>
</table>"""


class CheckReadmeFigures(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory()
        self.root = self.folder.name
        self.summaries = {"task": figures.summary_of(REPORT)}

    def tearDown(self):
        self.folder.cleanup()

    def readme(self, text):
        with open(os.path.join(self.root, "README.md"), "w", encoding="utf-8") as f:
            f.write(text)

    def test_reads_the_summary_rows_of_a_report(self):
        summary = self.summaries["task"]
        self.assertEqual(summary["duration"], "66.543 s")
        self.assertIn("(a & b)", summary["worst clearance (threshold 4.00 mm, allowed contacts apart)"])

    def test_figures_that_hold_pass_even_wrapped_over_lines(self):
        self.readme("It ran 66.5 s simulated, placement\nabout 0.3 mm; worst clearance 5.21 mm (threshold 4 mm),\n"
                    "tension 7.60-7.63 N after a right half.")
        claims = [("README.md", "66.5 s simulated", "task", figures.figure("duration", "66.5")),
                  ("README.md", "placement about 0.3 mm", "task", figures.placement_about(0.3)),
                  ("README.md", "worst clearance 5.21 mm (threshold 4 mm)", "task",
                   lambda s: figures.all_of(s, figures.figure("worst clearance", "5.21"),
                                            figures.figure_in_name("worst clearance", "4"))),
                  ("README.md", "7.60-7.63 N after a right half", "task",
                   figures.span("thread tension at the end of each pull", "7.60", "7.63", 0)),
                  ("README.md", "clearance", "task", figures.clearance_above_threshold)]
        self.assertEqual(figures.check_claims(self.root, self.summaries, claims), [])

    def test_a_stale_figure_fails_naming_what_the_run_gave(self):
        self.readme("worst clearance 5.32 mm and 66.4 s simulated")
        claims = [("README.md", "worst clearance 5.32 mm", "task", figures.figure("worst clearance", "5.32")),
                  ("README.md", "66.4 s simulated", "task", figures.figure("duration", "66.4"))]
        failures = figures.check_claims(self.root, self.summaries, claims)
        self.assertEqual(len(failures), 2)
        self.assertIn("README.md: 'worst clearance 5.32 mm' no longer holds: the run of apps/task gave "
                      "worst clearance: 5.21", failures[0])
        self.assertIn("duration: 66.5 (66.543 s)", failures[1])

    def test_a_fragment_the_readme_no_longer_quotes_or_a_lost_row_fails(self):
        self.readme("nothing quoted")
        claims = [("README.md", "66.5 s simulated", "task", figures.figure("duration", "66.5"))]
        self.assertIn("no longer quotes '66.5 s simulated'", figures.check_claims(self.root, self.summaries, claims)[0])
        self.readme("9 stitches")
        claims = [("README.md", "9 stitches", "task", figures.figure("stitches completed", "9"))]
        self.assertIn("has no such figure", figures.check_claims(self.root, self.summaries, claims)[0])

    def test_every_claim_names_a_fragment_its_readme_quotes(self):
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
        for readme, fragment, _, _ in figures.CLAIMS:
            with open(os.path.join(root, readme), encoding="utf-8") as f:
                self.assertIn(fragment, " ".join(f.read().split()), readme)


if __name__ == "__main__":
    unittest.main()
