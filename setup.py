from pathlib import Path

from setuptools import find_packages, setup

setup(
    name="ngdgfric",
    version="0.2.0",
    description="DG methods for 2D frictional contact with normal compliance on NGSolve (Porwal & Tanvi)",
    long_description=(Path(__file__).parent / "README.md").read_text(encoding="utf-8"),
    long_description_content_type="text/markdown",
    author="The ngdgfric developers",
    license="MIT",
    license_files=["LICENSE"],
    project_urls={"Paper (arXiv:2104.08266)": "https://arxiv.org/abs/2104.08266"},
    classifiers=[
        "Development Status :: 4 - Beta",
        "Intended Audience :: Science/Research",
        "Operating System :: POSIX :: Linux",
        "Programming Language :: Python :: 3",
        "Programming Language :: Python :: 3 :: Only",
        "Programming Language :: Python :: 3.10",
        "Programming Language :: Python :: 3.11",
        "Programming Language :: Python :: 3.12",
        "Topic :: Scientific/Engineering :: Mathematics",
        "Topic :: Scientific/Engineering :: Physics",
    ],
    keywords="contact mechanics, friction, normal compliance, discontinuous Galerkin, a posteriori error, hp, NGSolve",
    packages=find_packages(include=["ngdgfric", "ngdgfric.*"]),
    package_data={"ngdgfric": ["data/*.toml"]},
    python_requires=">=3.10",
    install_requires=[
        "ngsolve", "numpy", "matplotlib", "tomli; python_version < '3.11'",
        # threadpoolctl: OpenBLAS limited to one thread while solve/estimate/adapt run, scoped to the call
        # (idle OpenBLAS threads busy-wait: sparse back-substitutions 30-40 ms instead of 3-4 ms on 2 cores);
        # it replaces 40 lines of ctypes over /proc/self/maps that limited the whole process at import
        "threadpoolctl",
        # MKL PARDISO: the only pip-installable sparse factorisation with a Schur complement; the contact
        # solver condenses onto Gamma_C with it in one partial factorisation (results/linear_solvers.md).
        # Without it (other platforms) W comes from back-substitutions: same results, slower.
        "mkl; (sys_platform == 'linux' and platform_machine == 'x86_64')"
        " or (sys_platform == 'win32' and platform_machine == 'AMD64')",
    ],
    extras_require={
        # the studies run many independent cases through dask.distributed (issue: the two studies)
        "studies": ["dask[distributed]"],
        # the documentation site (docs/, README "Documentation"): sphinx builds it, autodoc (part of sphinx)
        # reads the docstrings; myst-nb reads Markdown (with myst-parser, its dependency) and executes the
        # gallery's notebooks and MyST notebooks at build time through
        # jupyter-cache and the ipykernel below; it needs no pandoc binary, unlike nbsphinx.
        # sphinx-mathjax-offline: MathJax 3 (24 MB) copied into the site, so that the formulas render offline;
        # the only pip-installable bundle (the alternative, server-side LaTeX, needs a TeX installation)
        "docs": ["sphinx", "myst-nb", "ipykernel", "sphinx-mathjax-offline"],
        # hypothesis: property tests of the condensed contact solver over random data (tests/test_reduced.py);
        # the docs extra: tests/test_docs.py builds the site when it is not built;
        # numpydoc: its validator checks the public docstrings (tests/test_docstrings.py); napoleon renders them
        # build: tests/test_packaging.py builds the wheel and the sdist (python -m build) and runs the quick tests on
        # the wheel installed in a fresh venv
        "test": ["pytest", "numpydoc", "build", "pyyaml", "ruff", "hypothesis", "nbclient", "nbformat", "nbconvert",
                 "ipykernel", "anywidget", "webgui_jupyter_widgets", "dask[distributed]", "ngdgfric[docs]"],
    },
    entry_points={"console_scripts": ["ngdgfric = ngdgfric.cli:main"]},
)
