"""build123d's import without scikit-learn and IPython: springcad never calls the build123d
functions that need them, and the real DBSCAN and pretty printer still work for anyone who
does."""

import subprocess
import sys

CODE = """
import sys
import numpy as np
import springcad.geometry.base
assert "sklearn" not in sys.modules, "scikit-learn was imported with build123d"
assert "sklearn.cluster" not in sys.modules, "the stand-in outlived the import"
assert "IPython" not in sys.modules, "IPython was imported with build123d"
assert "IPython.lib.pretty" not in sys.modules, "the stand-in outlived the import"
from build123d import Axis, Box
groups = Box(1, 2, 3).faces().group_by(Axis.Z)
text = str(groups)  # GroupBy.__str__ is IPython's pretty(): the real one, imported now
assert text.startswith("[[<build123d") and text.count("Face") == 6, text
import IPython.lib.pretty as pretty
from build123d.topology import shape_core
assert shape_core.pretty(groups) == pretty.pretty(groups)
import build123d.brep_from_stl as b
labels = b.DBSCAN(eps=0.5, min_samples=1).fit(np.array([[0.0, 0], [0.1, 0], [5, 5]])).labels_
assert list(labels) == [0, 0, 1], labels
from sklearn.cluster import DBSCAN
import sklearn.cluster._dbscan as real
assert DBSCAN is real.DBSCAN
print("ok")
"""


def test_build123d_without_sklearn_ipython_and_they_still_work():
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-2000:]
