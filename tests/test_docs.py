"""Every public entity of the Fortran library carries a FORD doc comment; scripts/docs builds the
documentation site (Sphinx, warnings as errors) with FORD's Fortran API pages in it.

The checker parses fortran/*/*.f90 (it is no compiler: it reads the code as this project writes
it) and lists, as "file:line: what", each of these without a doc comment:

- the module itself;
- every name made public (a `public ::` list or the `public` attribute): derived types,
  procedures, interfaces, constants and variables;
- the components and type-bound procedures of a public derived type;
- the dummy arguments of a public procedure (also inside an interface block).

A doc comment is a `!>` block right before the declaration, or `!!` on the declaration (at its
end, on a continuation line) or on the lines right after it. `python tests/test_docs.py`
prints the list.
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sorted((ROOT / "fortran").glob("*/*.f90"))
IDENT = r"[A-Za-z_]\w*"


def strip_comment(line: str) -> str:
    """The code of a line: everything before a `!` outside a string."""
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "!":
            return line[:i]
    return line


@dataclass
class Statement:
    first: int   # 0-based index of the first physical line
    last: int    # and of the last (continuations)
    code: str    # the code, continuations joined, comments removed, lower case


def statements(lines: list[str]) -> list[Statement]:
    out, i = [], 0
    while i < len(lines):
        code = strip_comment(lines[i]).strip()
        if not code:
            i += 1
            continue
        first, parts = i, []
        while True:
            code = strip_comment(lines[i]).strip()
            cont = code.endswith("&")
            parts.append(code.rstrip("&").lstrip("&").strip())
            if not cont or i + 1 >= len(lines):
                break
            i += 1
        out.append(Statement(first, i, " ".join(p for p in parts if p).lower()))
        i += 1
    return out


def documented(lines: list[str], st: Statement) -> bool:
    """A `!>` block right before, `!!` on the statement's lines, or `!!` lines right after."""
    if any("!!" in ln or "!>" in ln for ln in lines[st.first:st.last + 1]):
        return True
    if st.last + 1 < len(lines) and lines[st.last + 1].lstrip().startswith("!!"):
        return True
    j = st.first - 1
    while j >= 0 and lines[j].lstrip().startswith("!!"):
        j -= 1
    return j >= 0 and lines[j].lstrip().startswith("!>")


def declared_names(code: str) -> list[str]:
    """Names declared by a `type-spec [, attrs] :: a = 1, b(3), c` statement."""
    if "::" not in code:
        return []
    rest, depth, names, token = code.split("::", 1)[1], 0, [], ""
    for ch in rest + ",":
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
        if ch == "," and depth == 0:
            m = re.match(rf"\s*({IDENT})", token)
            if m:
                names.append(m.group(1))
            token = ""
        else:
            token += ch
    return names


PROC = re.compile(rf"^(?!end\b)(?:[\w(),=*\s]*\s)?(function|subroutine)\s+({IDENT})\s*(\((.*?)\))?")
TYPE = re.compile(rf"^type\s*(?:,[^:]*::|::|\s)\s*({IDENT})\s*$")


def undocumented(path: Path, root: Path = ROOT) -> list[str]:
    """'file:line: what' for each public entity of `path` without a doc comment."""
    lines = path.read_text().splitlines()
    sts = statements(lines)
    name = path.relative_to(root).as_posix()
    missing: list[str] = []

    def miss(st: Statement, what: str) -> None:
        if not documented(lines, st):
            missing.append(f"{name}:{st.first + 1}: {what}")

    public: set[str] = set()
    for st in sts:
        if re.match(r"^public\s*::", st.code):
            public.update(n.strip() for n in st.code.split("::", 1)[1].split(","))
        elif "::" in st.code and re.search(r",\s*public\b", st.code.split("::")[0]):
            public.update(declared_names(st.code))

    block: list[tuple[str, str]] = []         # (kind, name) of open type / interface / procedure
    module_part = True                        # before the module's `contains`
    for k, st in enumerate(sts):
        c = st.code
        if c.startswith("module ") and not c.startswith("module procedure"):
            miss(st, f"module {c.split()[1]}")
            continue
        if re.match(r"^end\s*(type|interface|function|subroutine)\b", c):
            if block:
                block.pop()
            continue
        if c == "contains":
            if not block:
                module_part = False
            continue
        m = TYPE.match(c)
        if m and not c.startswith("type("):
            block.append(("type", m.group(1)))
            if m.group(1) in public:
                miss(st, f"type {m.group(1)}")
            continue
        m = re.match(rf"^(abstract\s+)?interface\s*({IDENT})?", c)
        if m:
            block.append(("interface", m.group(2) or ""))
            if m.group(2) in public:
                miss(st, f"interface {m.group(2)}")
            continue
        m = PROC.match(c)
        if m:
            proc = m.group(2)
            block.append(("procedure", proc))
            if proc in public:
                miss(st, f"{m.group(1)} {proc}")
                args = [a.strip() for a in (m.group(4) or "").split(",") if a.strip()]
                check_arguments(sts, k, proc, args, miss)
            continue
        if block and block[-1][0] == "type" and block[-1][1] in public:
            if c not in ("private", "sequence") and "::" in c:
                for n in declared_names(c):
                    miss(st, f"component {block[-1][1]}%{n}")
            continue
        if module_part and not block and "::" in c and not c.startswith(("public", "private", "use ")):
            for n in declared_names(c):
                if n in public:
                    miss(st, f"{n}")
    return missing


def check_arguments(sts: list[Statement], k: int, proc: str, args: list[str], miss) -> None:
    """Each dummy argument of the procedure whose header is sts[k] is declared with a doc."""
    todo = set(args)
    for st in sts[k + 1:]:
        c = st.code
        if c == "contains" or re.match(r"^end\s*(function|subroutine)\b", c) or PROC.match(c):
            break
        if "::" in c:
            for n in declared_names(c):
                if n in todo:
                    todo.discard(n)
                    miss(st, f"argument {n} of {proc}")


def all_undocumented() -> list[str]:
    return [m for p in SOURCES for m in undocumented(p)]


def test_checker_finds_what_is_missing(tmp_path) -> None:
    """The checker against a module with one entity of each kind, documented or not."""
    src = tmp_path / "m.f90"
    src.write_text("""module m
    implicit none
    private
    public :: t, f, K, g
    integer, parameter :: K = 1
    !> doc
    integer, parameter, public :: L = 2
    type :: t
        real :: a   !! doc
        real :: b
    end type t
contains
    !> doc
    pure function f(x, y) result(z)
        real, intent(in) :: x  !! doc
        real, intent(in) :: y
        real :: z
        z = x + y
    end function f
    subroutine g(x)
        real, intent(in) :: x
            !! doc
    end subroutine g
end module m
""")
    found = undocumented(src, tmp_path)
    assert [f.split(": ", 1)[1] for f in found] == [
        "module m", "k", "type t", "component t%b", "argument y of f", "subroutine g"]


def test_every_public_fortran_entity_is_documented() -> None:
    missing = all_undocumented()
    assert not missing, f"{len(missing)} public entities without a FORD doc comment:\n" + \
        "\n".join(missing)


def _tool(name: str) -> str | None:
    exe = Path(sys.executable).parent / name
    return str(exe) if exe.exists() else shutil.which(name)


@pytest.mark.slow     # the whole site and FORD's pages
def test_scripts_docs_builds_the_site_and_the_fortran_pages(tmp_path) -> None:
    """scripts/docs builds the Sphinx site with warnings as errors (any warning fails it) and
    FORD's pages, one per Fortran module, into its fortran/ folder; the site links to them and
    its API reference documents every name the package exports."""
    if _tool("ford") is None or _tool("sphinx-build") is None:
        pytest.skip("FORD or Sphinx is not installed (scripts/setup installs them)")
    out = tmp_path / "site"
    proc = subprocess.run([str(ROOT / "scripts" / "docs"), str(out)],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    pages = {p.stem for p in (out / "fortran" / "module").glob("*.html")}
    modules = {p.stem for p in SOURCES}
    assert modules <= pages, sorted(modules - pages)
    assert 'href="fortran/index.html"' in (out / "fortran-api.html").read_text()
    import stickslip
    api = (out / "api.html").read_text()
    missing = [name for name in stickslip.__all__ if f'id="stickslip.{name}"' not in api]
    assert not missing, f"exported but not in the API reference: {missing}"
    # simulate is a C object standing for the Python function: its entry shows the function's
    # signature and docstring
    entry = re.sub(r"<[^>]+>", "", api[api.index('id="stickslip.simulate"'):][:3000])
    assert "simulate(scene, law=None, *, method, t_end" in entry and "Simulate scene with friction law" in entry
    for page in sorted((ROOT / "docs" / "guide").glob("*.md")):
        assert f'href="guide/{page.stem}.html"' in (out / "index.html").read_text(), page.name


@pytest.mark.slow     # a Sphinx build
def test_a_new_guide_page_joins_the_site(tmp_path) -> None:
    """A page dropped into docs/guide/ appears in the guide's table of contents, with no edit
    of any other file and no warning."""
    sphinx = _tool("sphinx-build")
    if sphinx is None:
        pytest.skip("Sphinx is not installed (scripts/setup installs it)")
    src = tmp_path / "docs"
    shutil.copytree(ROOT / "docs", src, ignore=shutil.ignore_patterns("_build"))
    shutil.copytree(ROOT / "benchmarks" / "results", tmp_path / "benchmarks" / "results")  # a figure
    shutil.copytree(ROOT / "examples", tmp_path / "examples")  # the guide includes examples/model_c.c
    (src / "guide" / "zz-new-topic.md").write_text("# A new topic\n\nText.\n")
    proc = subprocess.run([sphinx, "-b", "html", "-W", "--keep-going", "-q", str(src),
                           str(tmp_path / "out")], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert 'href="guide/zz-new-topic.html"' in (tmp_path / "out" / "index.html").read_text()


def _doctables():
    import importlib.util
    spec = importlib.util.spec_from_file_location("doctables", ROOT / "tools" / "doctables.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["doctables"] = module           # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def test_doc_tables_agree_with_their_results_files() -> None:
    """Every marked table of README.md and docs/ is what tools/doctables.py makes from the
    results file it names (and there are such tables: the benchmarks and the reproduction)."""
    doctables = _doctables()
    stale, count = [], 0
    for page in doctables.pages():
        new, changed = doctables.refresh(page)
        count += len(doctables.BLOCK.findall(page.read_text()))
        stale += [f"{page.relative_to(ROOT)}:{line}" for line in changed]
    assert count >= 10
    assert not stale, "tables that disagree with their results files (python tools/doctables.py " \
        "refreshes them):\n" + "\n".join(stale)


def test_doc_tables_notice_a_changed_number(tmp_path) -> None:
    """A table of selected rows and columns is rendered from a CSV with its provenance; when a
    number in the CSV changes, the check reports the table, and a refresh makes them agree."""
    doctables = _doctables()
    from cases import _common
    from harness.provenance import write_provenance
    csv = _common.write_csv(tmp_path / "r.csv", ["law [-]", "x [m]", "n [-]"],
                            [["a", 0.123456789, 7], ["b", 2.5e-9, 8]])
    write_provenance(tmp_path, "cases.demo", [csv], ["--outdir", "x"])
    page = tmp_path / "page.md"
    page.write_text("Text.\n\n<!-- table: r.csv\ncolumns: law [-] = law; x [m] = x [m]\n"
                    "where: law [-] = a\ndigits: 3\n-->\n<!-- end table -->\n")
    text, changed = doctables.refresh(page)
    assert changed == [3]
    assert "| law | x [m] |\n|---|---|\n| a | 0.123 |\n" in text and "| b |" not in text
    assert "written by `python -m cases.demo --outdir x`" in text
    page.write_text(text)
    assert doctables.refresh(page)[1] == []
    _common.write_csv(csv, ["law [-]", "x [m]", "n [-]"], [["a", 0.124, 7]])
    assert doctables.refresh(page)[1] == [3]


def test_doc_tables_format_a_column_one_way(tmp_path) -> None:
    """A column of integers is shown whole; a column that mixes integral and other numbers
    (a float CSV cell written as "597124") shows all of them to `digits`."""
    doctables = _doctables()
    (tmp_path / "r.csv").write_text("n [-],ns [ns]\n61,27901.5\n50,597124\n")
    page = tmp_path / "page.md"
    page.write_text("<!-- table: r.csv\ndigits: 3\n-->\n<!-- end table -->\n")
    text, _ = doctables.refresh(page)
    assert "| 61 | 2.79e+04 |" in text and "| 50 | 5.97e+05 |" in text


if __name__ == "__main__":
    print("\n".join(all_undocumented()) or "every public entity is documented")
