"""FreeCAD Test-workbench entry (``FreeCAD -t TestMetamaterialApp``): runs tests/fc through pytest."""
import os
import unittest

_REPO = os.path.dirname(os.path.abspath(__file__))


class TestMetamaterialApp(unittest.TestCase):
    def test_app_suite(self):
        import pytest
        rc = pytest.main(["-q", "-p", "no:cacheprovider", os.path.join(_REPO, "tests", "fc")])
        self.assertEqual(int(rc), 0, "tests/fc failed (see the pytest output above)")
