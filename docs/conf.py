"""Sphinx configuration of flexarm's documentation site (``docs/_build/html``).

Built by the test command (``tests/test_docs.py``) with ``-W``: a warning, a broken
cross-reference or a failing gallery example fails the build.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")
os.environ.setdefault("MPLBACKEND", "Agg")

import flexarm  # noqa: E402

project = "flexarm"
author = "flexarm developers"
copyright = "2026, flexarm developers"
version = release = flexarm.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
    "sphinxarg.ext",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "examples/README.rst", "images/README.md", "sg_execution_times.rst"]
templates_path = ["_templates"]
root_doc = "index"

autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": False}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks = set()
numpydoc_xref_param_type = False
myst_heading_anchors = 3
nitpicky = True
#: Outside the package: no inventories are fetched (the build runs offline).
#: Attributes of a numpydoc "Attributes" section and module constants are described in
#: text, not as objects of their own; private helpers are not documented.
nitpick_ignore_regex = [(r"py:.*", r"(numpy|np|scipy|matplotlib|collections|csv|pathlib|"
                                   r"typing|pyvista|trimesh|meshio|h5py|pandas|exudyn)\b.*"),
                        (r"py:(attr|data)", r".*"), (r"py:.*", r"(.*\.)?_\w+")]

html_theme = "pydata_sphinx_theme"
html_title = "flexarm"
html_static_path = []
#: The left sidebar shows the current page's branch only: resolving the whole tree of
#: ~330 API pages for every page was over half of writing the site.
html_theme_options = {"navigation_depth": 2, "show_toc_level": 2, "collapse_navigation": True,
                      "secondary_sidebar_items": ["page-toc"]}



def _modules_first():
    """Autosummary reads ``package.name`` as the package's attribute first; where a
    package re-exports a function under its module's name (``flexarm.assembly.emodel``),
    the module is what the reference lists."""
    import importlib
    import importlib.util

    from sphinx.ext import autosummary
    from sphinx.ext.autosummary import generate

    original = autosummary._import_by_name

    def by_name(name, grouped_exception=True):
        if name.startswith("flexarm.") and importlib.util.find_spec(name) is not None:
            module = importlib.import_module(name)
            parent = name.rsplit(".", 1)[0]
            return module, importlib.import_module(parent), parent
        return original(name, grouped_exception)

    autosummary._import_by_name = by_name
    generate._import_by_name = by_name


_modules_first()


def _skip_foreign(app, what, name, obj, skip, options):
    """Members a flexarm class inherits from another package (a matplotlib Figure's
    ``set``) are that package's to document."""
    module = getattr(obj, "__module__", None) or ""
    if what == "class" and module and not module.startswith("flexarm"):
        return True
    return skip


def _defined_at(key: str) -> bool:
    """Whether the object ``key`` names is defined in the module the key puts it in."""
    import importlib

    module, _, name = key.rpartition(".")
    try:
        obj = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError, ValueError):
        return False
    return getattr(obj, "__module__", module) == module


def _resolve_short(app, env, node, contnode):
    """A cross-reference by a short or package-level name (``ArmModel``,
    ``flexarm.fe.factorize``, ``compare_dynamic.compare_modal``): the one documented
    object whose full name ends with it (within the named package, if any)."""
    from sphinx.util.nodes import make_refnode

    if node.get("refdomain") != "py":
        return None
    target = "".join(node["reftarget"].split()).lstrip(".~")
    domain = env.get_domain("py")
    parts = target.split(".")
    package = ".".join(parts[:-1]) if target.startswith("flexarm.") else ""
    name = parts[-1] if package else target
    kinds = {"func": ("function", "method"), "meth": ("method", "function"),
             "class": ("class", "exception"), "exc": ("exception", "class"),
             "mod": ("module",)}.get(node.get("reftype"))
    hits = [k for k, o in domain.objects.items() if (k.endswith("." + name) or k == name)
            and k.startswith(package) and (kinds is None or o.objtype in kinds)]
    hits = [k for k in hits if "._" not in k] or hits
    if len(hits) > 1:  # an object documented where it is defined and where re-exported
        hits = [k for k in hits if _defined_at(k)] or hits
    if len(hits) > 1:  # several objects of that name: the one nearest the referring module
        here = (node.get("py:module") or "").split(".")

        def shared(k):
            n = 0
            for a, b in zip(k.split("."), here, strict=False):
                if a != b:
                    break
                n += 1
            return n

        best = max(shared(k) for k in hits)
        hits = [k for k in hits if shared(k) == best]
    if len(hits) != 1:
        return None
    obj = domain.objects[hits[0]]
    return make_refnode(app.builder, node["refdoc"], obj.docname, obj.node_id, contnode,
                        hits[0])


def setup(app):
    app.connect("autodoc-skip-member", _skip_foreign)
    app.connect("missing-reference", _resolve_short)


sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "ignore_pattern": r"__init__\.py|(^|/)_\w+\.py",
    "image_scrapers": ("matplotlib",),
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "within_subsection_order": "FileNameSortKey",
}
