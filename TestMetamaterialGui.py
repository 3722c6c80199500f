"""FreeCAD Test-workbench entry for the GUI tests (``freecad -t TestMetamaterialGui``): tests/gui via pytest."""
import os
import unittest

_REPO = os.path.dirname(os.path.abspath(__file__))


class TestMetamaterialGui(unittest.TestCase):
    def test_gui_suite(self):
        import pytest
        rc = pytest.main(["-q", "-p", "no:cacheprovider", os.path.join(_REPO, "tests", "gui")])
        self.assertEqual(int(rc), 0, "tests/gui failed (see the pytest output above)")
