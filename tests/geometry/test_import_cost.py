"""build123d's import without scikit-learn: springcad never calls the one build123d function
that needs it, and the real DBSCAN still works for anyone who does."""

import subprocess
import sys

CODE = """
import sys
import numpy as np
import springcad.geometry.base
assert "sklearn" not in sys.modules, "scikit-learn was imported with build123d"
assert "sklearn.cluster" not in sys.modules, "the stand-in outlived the import"
import build123d.brep_from_stl as b
labels = b.DBSCAN(eps=0.5, min_samples=1).fit(np.array([[0.0, 0], [0.1, 0], [5, 5]])).labels_
assert list(labels) == [0, 0, 1], labels
from sklearn.cluster import DBSCAN
import sklearn.cluster._dbscan as real
assert DBSCAN is real.DBSCAN
print("ok")
"""


def test_build123d_without_sklearn_and_dbscan_still_works():
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-2000:]
