"""The documentation site: built from the repository with every warning (and every broken
cross-reference) an error, its gallery run, its pages shown by a headless browser with
every picture loaded; the README short, with every section it once held moved into the
site; the Python API page's blocks run as written.
"""

from __future__ import annotations

import ast
import importlib
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
SITE = DOCS / "_build" / "html"
API_PAGE = DOCS / "guides" / "python_api.md"
#: The README's sections before the site took them (2026-11-26).
FORMER_HEADINGS = (
    "Two commands", "What the demo shows", "Benchmarks", "Layout", "Command line",
    "Superelements (reduction)", "The robot and its arm models",
    "Bring your own robot: the ABB IRB 4600 from its published URDF", "The flexible arm",
    "Exports for controllers, Nastran and multibody simulation",
    "Contact applications (loaded circle, chatter)",
    "From measurements to a better model: `lab` → `compare` → `diagnose` → `compare`",
    "From a vibration lab: universal files → `ema` → `compare` (MAC) → `diagnose`",
    "Python API", "Solver backends", "Links past one machine (PETSc/MUMPS + SLEPc under MPI)",
    "Dependencies and why", "Measurement files")


def test_readme_is_short_and_its_links_resolve():
    text = README.read_text()
    assert len(text.splitlines()) < 150
    assert "flexarm demo" in text and 'python -m pytest -q -m "not slow" -n auto' in text
    for target in re.findall(r"\]\(([^)#]+)\)", text):
        assert (ROOT / target).exists(), target


def test_every_former_readme_section_has_a_home_in_the_site():
    headings = set()
    for page in DOCS.rglob("*.md"):
        if "_build" in page.parts:
            continue
        headings |= {m.group(1).strip() for m in re.finditer(r"^#+ (.+)$", page.read_text(),
                                                              flags=re.M)}
    missing = [h for h in FORMER_HEADINGS if not any(x.startswith(h) for x in headings)]
    assert not missing, missing


def _api_blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", API_PAGE.read_text(), flags=re.S)


def test_the_api_page_has_the_main_jobs():
    code = "\n".join(_api_blocks())
    for job in ("part_modes", "reduce_part", "build_arm", "compliance_report", "run_lab",
                "compare(", "run_diagnosis", "run_circle", "run_chatter"):
        assert job in code, job


def test_the_api_blocks_run(capsys):
    namespace: dict = {}
    for block in _api_blocks():
        exec(compile(block, str(API_PAGE), "exec"), namespace)  # noqa: S102 - our own page
    printed = capsys.readouterr().out
    assert namespace["clamped"].freq_hz[:3] == pytest.approx([41.84, 41.85, 259.3], rel=2e-3)
    assert namespace["se"].n_dofs == 22
    assert namespace["report"].weakest == "y"
    assert namespace["report"].deflection[1] * 1e3 == pytest.approx(6.2, abs=0.05)
    assert "ACCEPTED: joint 2 backlash" in printed
    assert namespace["chatter"].kcb == 5e5


@pytest.fixture(scope="module")
def site():
    """The site built as ``python -m sphinx -W -n`` builds it (gallery examples run)."""
    shutil.rmtree(SITE, ignore_errors=True)
    for generated in (DOCS / "reference" / "generated", DOCS / "auto_examples"):
        shutil.rmtree(generated, ignore_errors=True)
    env = dict(os.environ, MPLBACKEND="Agg", PYVISTA_OFF_SCREEN="true")
    run = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-q", "-n", "-W",
                          "--keep-going", str(DOCS), str(SITE)], capture_output=True,
                         text=True, env=env, cwd=ROOT)
    assert run.returncode == 0, run.stderr[-3000:]
    return SITE


def test_the_site_builds_without_a_warning(site):
    assert (site / "index.html").is_file()
    pictures = sorted((site / "_images").glob("sphx_glr_plot_*_0*.png"))
    examples = {re.match(r"sphx_glr_(plot_\d+_\w+?)_\d+\.png", p.name).group(1)
                for p in pictures}
    assert len(examples) >= 8, examples


def test_every_command_and_public_name_has_a_reference_entry(site):
    from flexarm.cli import COMMANDS

    cli = (site / "reference" / "cli.html").read_text()
    missing = [c for c in COMMANDS if f'id="{c}"' not in cli and f"flexarm {c}" not in cli]
    assert not missing, missing
    ids = set()
    for page in (site / "reference" / "generated").glob("*.html"):
        ids |= set(re.findall(r'id="(flexarm\.[\w.]+)"', page.read_text()))
    undocumented = []
    for path in sorted((ROOT / "flexarm").rglob("*.py")):
        if path.name == "__main__.py" or "cli" in path.parts:
            continue  # the commands are documented by their parser, above
        module = ".".join(path.relative_to(ROOT).with_suffix("").parts)
        module = module.removesuffix(".__init__")
        tree = ast.parse(path.read_text())
        names = next((ast.literal_eval(n.value) for n in tree.body if isinstance(n, ast.Assign)
                      and any(getattr(t, "id", "") == "__all__" for t in n.targets)), [])
        mod = importlib.import_module(module)
        for name in names:
            obj = getattr(mod, name, None)
            if callable(obj) and getattr(obj, "__module__", None) == module:
                if f"{module}.{name}" not in ids:
                    undocumented.append(f"{module}.{name}")
    assert not undocumented, undocumented


def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    return None


@pytest.mark.skipif(_chromium() is None or shutil.which("chromedriver") is None,
                    reason="needs Debian's chromium and chromium-driver (install.sh --test)")
def test_a_browser_shows_the_pages_with_every_picture(site):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = _chromium()
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                 "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
    try:
        pages = [site / "index.html", site / "auto_examples" / "index.html"]
        pages += sorted((site / "auto_examples").glob("plot_*.html"))
        for page in pages:
            driver.get(page.as_uri())
            images = driver.execute_script(
                "return Array.from(document.images).map(i => [i.src, i.complete && "
                "i.naturalWidth > 0])")
            assert images, page
            broken = [src for src, ok in images if not ok]
            assert not broken, (page.name, broken)
    finally:
        driver.quit()


def _benchmark_rows() -> list[str]:
    text = (DOCS / "benchmarks.md").read_text()
    return [ln for ln in text.splitlines()
            if ln.startswith("| ") and not ln.startswith(("| script", "|---"))]


def test_every_benchmark_figure_names_its_command_date_and_load():
    """Each row of the benchmark table: the command that prints it (a script that exists),
    the date it was measured and the machine's load, or the plain statement that the date
    or load was not recorded (figures from before this rule)."""
    rows = _benchmark_rows()
    assert len(rows) >= 10
    for row in rows:
        command = re.search(r"`python (benchmarks/\w+\.py)[^`]*`", row)
        assert command and (ROOT / command.group(1)).is_file(), row[:80]
        assert re.search(r"20\d\d-\d\d-\d\d|date not recorded", row), row[:80]
        assert re.search(r"load \d|load not recorded", row), row[:80]
