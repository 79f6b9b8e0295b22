import re
import subprocess
import sys
import unittest

import fixture_results
from method_styles import METHOD_STYLES, method_style


class MethodStyle(unittest.TestCase):
    def test_every_shipped_method_has_its_own_colour_and_marker(self):
        self.assertEqual(set(METHOD_STYLES), {"path_traced", "mamba", "dense_grid", "cards", "hash_grid"})
        self.assertEqual(len({s["color"] for s in METHOD_STYLES.values()}), 5)
        self.assertEqual(len({s["marker"] for s in METHOD_STYLES.values()}), 5)
        self.assertEqual(method_style("mamba"), METHOD_STYLES["mamba"])

    def test_another_method_gets_an_unused_style_the_same_in_every_process(self):
        style = method_style("mamba_restir_v2")
        self.assertRegex(style["color"], re.compile(r"^#[0-9a-f]{6}$"))
        self.assertNotIn(style["color"], {s["color"] for s in METHOD_STYLES.values()})
        # Python's str hash is salted per process: the style must not depend on it.
        other = subprocess.run([sys.executable, "-c", "import sys; sys.path.insert(0, sys.argv[1]); "
                                "from method_styles import method_style; print(method_style('mamba_restir_v2'))",
                                str(fixture_results.ANALYSIS)], capture_output=True, text=True, check=True).stdout
        self.assertEqual(other.strip(), str(style))

    def test_callers_get_a_copy(self):
        method_style("cards")["color"] = "#000000"
        self.assertEqual(method_style("cards")["color"], METHOD_STYLES["cards"]["color"])


if __name__ == "__main__":
    unittest.main()
