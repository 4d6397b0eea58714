from setuptools import find_packages, setup

setup(
    name="ngdgfric",
    version="0.1.0",
    description="DG methods for 2D frictional contact with normal compliance on NGSolve (Porwal & Tanvi)",
    packages=find_packages(include=["ngdgfric", "ngdgfric.*"]),
    package_data={"ngdgfric": ["data/*.toml"]},
    python_requires=">=3.10",
    install_requires=["ngsolve", "numpy", "matplotlib", "tomli; python_version < '3.11'"],
    extras_require={
        # the studies run many independent cases through dask.distributed (issue: the two studies)
        "studies": ["dask[distributed]"],
        "test": ["pytest", "ruff", "nbclient", "nbformat", "nbconvert", "ipykernel", "anywidget",
                 "webgui_jupyter_widgets", "dask[distributed]"],
    },
    entry_points={"console_scripts": ["ngdgfric = ngdgfric.cli:main"]},
)
