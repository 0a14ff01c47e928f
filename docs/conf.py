"""Sphinx configuration of hbfriction's documentation (scripts/build-docs.sh builds it).

The pages are Markdown (MyST). The reference pages are generated when the site is built: the
command-line flags and output columns, the contact laws' parameters and the system-file keys come
from the `hbf` executable itself (`hbf reference`, read by _ext/hbf_reference.py), the C++ API
from the public headers through Doxygen and Breathe, the Python API from the built module, and
the gallery from running examples/python. Environment:
  HBF_EXECUTABLE   the hbf program to document (required)
  HBF_DOXYGEN_XML  Doxygen's XML output of include/hbf (required)
  PYTHONPATH       must reach the built hbfriction package
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "_ext"))

project = "hbfriction"
author = "the hbfriction developers"
copyright = "the hbfriction developers, BSD-3-Clause"

import hbfriction  # noqa: E402  the documented module, also the version's source

release = hbfriction.__version__
version = ".".join(release.split(".")[:2])

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "breathe",
    "sphinx_gallery.gen_gallery",
    "hbf_reference",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "images/front_figure.py", "gallery/*.md5", "gallery/*.ipynb",
                    "gallery/*.py", "gallery/*.zip"]
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
suppress_warnings = []

smartquotes = False  # "--config" stays two hyphens, quotes stay straight: flags are typed

html_theme = "sphinx_rtd_theme"
html_title = "hbfriction %s" % release
html_static_path = ["_static"]
html_css_files = ["hbf.css"]
html_show_sourcelink = False

breathe_projects = {"hbfriction": os.environ["HBF_DOXYGEN_XML"]}
breathe_default_project = "hbfriction"
breathe_default_members = ("members",)

autodoc_default_options = {"members": True, "undoc-members": False}
autodoc_typehints = "signature"

sphinx_gallery_conf = {
    "examples_dirs": "../examples/python",
    "gallery_dirs": "gallery",
    "filename_pattern": r".*\.py$",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "plot_gallery": "True",
}
