"""The documentation runs: the docstrings' examples (doctest), the Python blocks of the READMEs
and of the user guide (docs/guide/),
``help()`` naming every option, the type stubs matching the functions, and the examples in
``examples/python/`` run as a user would run them, without a display."""

import ast
import doctest
import inspect
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import quadopt
from helpers import ROOT

PACKAGE = Path(quadopt.__file__).parent


def test_docstring_examples():
    pytest.importorskip("meshio")
    failures, tried = doctest.testmod(quadopt, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert tried >= 15 and failures == 0


def python_blocks(page: Path):
    """The page's ```python blocks that are not marked as illustrations (the line before the
    fence an ``<!-- illustration: ... -->`` comment), as (line, code); tests/docs.rs holds every
    other kind of block to the same rule."""
    lines = page.read_text().split("\n")
    found, i = [], 0
    while i < len(lines):
        if lines[i].strip() == "```python":
            before = next((l.strip() for l in reversed(lines[:i]) if l.strip()), "")
            end = lines.index("```", i + 1)
            if not before.startswith("<!-- illustration"):
                found.append((i + 1, "\n".join(lines[i + 1:end]) + "\n"))
            i = end
        i += 1
    return found


DOC_PAGES = [ROOT / "README.md", ROOT / "python" / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
DOC_BLOCKS = [(page, line, code) for page in DOC_PAGES for line, code in python_blocks(page)]


def test_the_docs_have_python_blocks():
    pages = {page.name if page.parent.name != "guide" else f"guide/{page.name}" for page, _, _ in DOC_BLOCKS}
    assert {"README.md", "guide/python.md"} <= pages, pages
    assert len(DOC_BLOCKS) >= 6


@pytest.mark.parametrize("page,line,code", DOC_BLOCKS,
                         ids=[f"{p.relative_to(ROOT)}:{n}" for p, n, _ in DOC_BLOCKS])
def test_doc_python_blocks_run(page, line, code, capsys, monkeypatch):
    """Every Python block of the README and the guide runs from the repository's root, as a
    reader would paste it."""
    if "meshio" in code:
        pytest.importorskip("meshio")
    monkeypatch.chdir(ROOT)
    exec(compile("\n" * line + code, str(page), "exec"), {"__name__": "__doc_example__"})
    out = capsys.readouterr().out
    assert out.strip(), f"{page}:{line}: the example prints nothing"


@pytest.mark.parametrize("readme", [ROOT / "README.md", ROOT / "python" / "README.md"])
def test_readme_quick_start_is_short(readme, capsys):
    (_, code), *_ = python_blocks(readme)
    assert len(code.strip().splitlines()) <= 10, "the README's example is ten lines at most"
    exec(compile(code, str(readme), "exec"), {})
    assert "->" in capsys.readouterr().out


def test_help_reads_well():
    text = inspect.getdoc(quadopt.optimize)
    for name in inspect.signature(quadopt.optimize).parameters:
        assert re.search(rf"^\s*{name}:", text, re.M), f"optimize's docstring does not describe {name}"
    for f in (quadopt.quality, quadopt.optimize_mesh, quadopt.OptimizeResult, quadopt.QualityResult,
              quadopt.MeshError, quadopt.CancelledError, quadopt.Progress):
        assert f.__doc__ and len(f.__doc__) > 40, f"{f.__name__} has no documentation"
    assert "Sweeps done" in (quadopt.Progress.iteration.__doc__ or "")
    signature = str(inspect.signature(quadopt.optimize))
    assert signature.startswith("(points: Any, faces: Any, *, fixed: Any = None"), signature


def stub_functions(path: Path):
    tree = ast.parse(path.read_text())
    found = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            a = node.args
            found.setdefault(node.name, []).append(
                ([x.arg for x in a.posonlyargs + a.args], [x.arg for x in a.kwonlyargs]))
    return found, {n.name for n in tree.body if isinstance(n, ast.ClassDef)}


def test_stubs_match_the_functions():
    functions, classes = stub_functions(PACKAGE / "__init__.pyi")
    for name in quadopt.__all__:
        obj = getattr(quadopt, name)
        if inspect.isfunction(obj):
            params = inspect.signature(obj).parameters.values()
            positional = [p.name for p in params if p.kind == p.POSITIONAL_OR_KEYWORD]
            keywords = [p.name for p in params if p.kind == p.KEYWORD_ONLY]
            for stub_positional, stub_keywords in functions[name]:
                assert stub_positional == positional, name
                if name == "optimize_mesh":  # its **options spelled out
                    assert stub_keywords[: len(keywords)] == keywords
                    assert set(stub_keywords[len(keywords):]) <= set(inspect.signature(quadopt.optimize).parameters)
                else:
                    assert stub_keywords == keywords, name
        elif name != "__version__":
            assert name in classes or f"{name} as {name}" in (PACKAGE / "__init__.pyi").read_text(), name
    ext_functions, ext_classes = stub_functions(PACKAGE / "_quadopt.pyi")
    assert {"optimize", "quality"} <= set(ext_functions) and "Progress" in ext_classes
    assert (PACKAGE / "py.typed").exists()


def run_example(name, *args, tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["MPLBACKEND"] = "Agg"
    r = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / name), *map(str, args)],
                       capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_the_plate_example(tmp_path):
    meshio = pytest.importorskip("meshio")
    pytest.importorskip("gmsh")
    pytest.importorskip("matplotlib")
    out = run_example("plate_with_holes.py", "--out", tmp_path / "out", tmp_path=tmp_path)
    print(out)
    stats = dict(re.findall(r"^(input|output)\s*: min (\S+),", out, re.M))
    assert float(stats["output"]) > float(stats["input"])
    vtu = meshio.read(tmp_path / "out" / "plate_optimized.vtu")
    q = np.concatenate([np.ravel(v) for b, v in zip(vtu.cells, vtu.cell_data["scaled_jacobian"])
                        if b.type in ("quad", "triangle")])
    assert np.isclose(q.min(), float(stats["output"]), atol=1e-4) and (q > 0).all()
    png = tmp_path / "out" / "plate_before_after.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000


def test_the_versions_agree():
    import importlib.metadata

    cargo = (ROOT / "Cargo.toml").read_text()
    root = re.search(r'^version = "(.*)"', cargo, re.M).group(1)
    python = re.search(r'^version = "(.*)"', (ROOT / "python" / "Cargo.toml").read_text(), re.M).group(1)
    assert quadopt.__version__ == root == python == importlib.metadata.version("quadopt")
