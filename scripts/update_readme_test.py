#!/usr/bin/python3
"""Tests of scripts/update_readme.py (CTest update_readme_test): the README check fails when a
number in results/ or in the README changes, and a new method joins the tables."""

import copy
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import update_readme  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class PatchedResults(update_readme.Results):
    """The committed results with rows of one summary changed in memory."""

    def __init__(self, experiment, change):
        super().__init__(os.path.join(ROOT, "results"))
        self.summary(experiment)
        path, rows = self._cache[experiment]
        self._cache[experiment] = (path, change(copy.deepcopy(rows)))


class UpdateReadme(unittest.TestCase):
    def setUp(self):
        with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
            self.readme = f.read()

    def test_a_changed_result_changes_the_readme(self):
        def change(rows):
            for r in rows:
                if r["method"] == "trifocal_line_ekf" and float(r["noise.endpoint_px"]) == 2.5:
                    r["rot_err_deg_mean"] = "0.987"
            return rows

        filled = update_readme.fill(self.readme, PatchedResults("noise_sweep", change))
        self.assertNotEqual(filled, self.readme)
        self.assertIn("| `trifocal_line_ekf` | 0.987° |", filled)

    def test_a_changed_readme_number_is_put_back(self):
        results = update_readme.Results(os.path.join(ROOT, "results"))
        edited = self.readme.replace("<!-- generated:fig4_against_paper -->", "<!-- generated:fig4_against_paper -->9", 1)
        self.assertNotEqual(edited, self.readme)
        self.assertEqual(update_readme.fill(edited, results), update_readme.fill(self.readme, results))

    def test_a_new_method_joins_the_tables(self):
        def add_method(rows):
            return rows + [dict(r, method="taylor_line_sfm") for r in rows if r["method"] == "yu_point_ekf"]

        filled = update_readme.fill(self.readme, PatchedResults("feature_count", add_method))
        self.assertIn("| `taylor_line_sfm` | 30 % |", filled)

    def test_unknown_blocks_and_missing_results_are_errors(self):
        results = update_readme.Results(os.path.join(ROOT, "results"))
        with self.assertRaises(update_readme.ResultsError):
            update_readme.fill("<!-- generated:no_such_block --><!-- /generated -->", results)
        with self.assertRaises(update_readme.ResultsError):
            update_readme.fill(self.readme, update_readme.Results(os.path.join(ROOT, "no_such_results")))

    def test_markdown_rows_are_one_tables_only(self):
        import tempfile
        with tempfile.TemporaryDirectory() as root:
            os.makedirs(os.path.join(root, "frontend"))
            with open(os.path.join(root, "frontend", "t.md"), "w", encoding="utf-8") as f:
                f.write("Generated.\n\n| scene | recall |\n|---|---:|\n| room | 0.9 |\n\nMore:\n\n"
                        "| scene | draws |\n|---|---:|\n| room | 10 |\n")
            results = update_readme.Results(root)
            _, rows = results.markdown_rows("frontend", "t.md")
            _, second = results.markdown_rows("frontend", "t.md", table=1)
            with self.assertRaises(update_readme.ResultsError):
                results.markdown_rows("frontend", "t.md", table=2)
        self.assertEqual(rows, [{"scene": "room", "recall": "0.9"}])
        self.assertEqual(second, [{"scene": "room", "draws": "10"}])

    def test_numbers_are_written_with_three_significant_digits(self):
        self.assertEqual(update_readme.sig(0.15312), "0.153")
        self.assertEqual(update_readme.sig(3.84e-6), "3.8e-6")
        self.assertEqual(update_readme.sig(27968.4), "27968")
        self.assertEqual(update_readme.mm(0.00145), "1.45 mm")
        self.assertEqual(update_readme.mm(28.0), "28 m")


if __name__ == "__main__":
    unittest.main()
