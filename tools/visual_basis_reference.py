#!/usr/bin/python3
"""A scikit-learn reference for the mouth model's visual basis (engine/animation/visual_basis.h): PCA + FastICA.

Not part of the product: tests/animation/visual_basis_crosscheck_test.cpp runs it. It shares no code with the
C++ side: the columns are standardised here in numpy, PCA is sklearn.decomposition.PCA (an SVD of the data
rather than an eigen-decomposition of the covariance) with whiten=True, and the rotation is
sklearn.decomposition.FastICA (parallel = symmetric, fun="logcosh") on the whitened components.

    /usr/bin/python3 tools/visual_basis_reference.py DATA.csv COMPONENTS.csv [--components K] [--seed N]

DATA.csv has a header row and one frame per row (a column per visual parameter). COMPONENTS.csv gets a header
c0..c{K-1} and one row per frame: the independent components, each scaled to unit variance. Printed on stdout,
the last line is the fraction of the standardised variance the K PCA components keep (repr, full precision).

Numbers: Debian's python3-numpy and python3-sklearn; call /usr/bin/python3 explicitly.
"""

import argparse
import sys

import numpy
from sklearn.decomposition import PCA, FastICA


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data")
    parser.add_argument("output")
    parser.add_argument("--components", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)

    x = numpy.loadtxt(args.data, delimiter=",", skiprows=1, ndmin=2)
    # Standardise: population deviation (ddof = 0); a constant column keeps scale 1.
    deviation = x.std(axis=0)
    deviation[deviation == 0.0] = 1.0
    standardised = (x - x.mean(axis=0)) / deviation

    pca = PCA(n_components=args.components, whiten=True, svd_solver="full")
    whitened = pca.fit_transform(standardised)
    ica = FastICA(n_components=args.components, algorithm="parallel", whiten=False, fun="logcosh",
                  max_iter=10000, tol=1e-10, random_state=args.seed)
    sources = ica.fit_transform(whitened)
    sources = (sources - sources.mean(axis=0)) / sources.std(axis=0)

    header = ",".join("c%d" % k for k in range(args.components))
    numpy.savetxt(args.output, sources, delimiter=",", header=header, comments="", fmt="%.17g")
    print("iterations", ica.n_iter_)
    print(repr(float(pca.explained_variance_ratio_.sum())))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
