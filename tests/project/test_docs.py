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
end, on a continuation line) or on the lines right after it. `python tests/project/test_docs.py`
prints the list.
"""
from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
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
    for package in ("tools", "harness"):                # the {num} role's extension reads with them
        shutil.copytree(ROOT / package, tmp_path / package, ignore=shutil.ignore_patterns("__pycache__"))
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


# ---------------------------------------------------------------- numbers in the prose, from their sources
def _docnumbers():
    sys.path.insert(0, str(ROOT))
    from tools import docnumbers
    return docnumbers


def test_a_number_is_shown_from_its_source(tmp_path) -> None:
    """The role's number is read from a named-numbers file or a CSV cell, shown in the form it
    is written (decimals, exponent form, a factor, significant digits), and a refresh rewrites
    the page's number when the source changes; a bad key names what the file has."""
    dn = _docnumbers()
    (tmp_path / "r.json").write_text(dn.numbers_json({"cpu_s": (231.46, "s", "CPU"), "err": 8.46e-6}))
    (tmp_path / "t.csv").write_text("law [-],mode [-],nfev [-]\na,h=1e-3,20000\na,auto,30012345\n")
    assert dn.shown("230 s", "r.json:cpu_s", tmp_path)[0] == "231 s"
    assert dn.shown("about 231.5 s of CPU", "r.json:cpu_s", tmp_path)[0] == "about 231.5 s of CPU"
    assert dn.shown("8.5e-6 m", "r.json:err", tmp_path)[0] == "8.5e-6 m"
    assert dn.shown("8.46 um", "r.json:err*1e6", tmp_path)[0] == "8.46 um"
    assert dn.shown("30000000", "t.csv:nfev [-][law [-]=a,mode [-]=auto]~2", tmp_path)[0] == "30000000"
    assert dn.shown("1500 times", "t.csv:nfev [-][mode [-]=auto]*5e-5~2", tmp_path)[0] == "1500 times"
    with pytest.raises(dn.SourceError, match="has no number 'cpu' .*it has: cpu_s, err"):
        dn.shown("1 s", "r.json:cpu", tmp_path)
    with pytest.raises(dn.SourceError, match="picks 2 rows, not one"):
        dn.shown("1", "t.csv:nfev [-][law [-]=a]", tmp_path)
    assert dn.shown("20000 to", "t.csv:nfev [-][law [-]=a]@min", tmp_path)[0] == "20000 to"
    assert dn.shown("3e7", "t.csv:nfev [-][law [-]=a]@max", tmp_path)[0] == "3e7"
    ratio = "t.csv:nfev [-][mode [-]=auto]/nfev [-][mode [-]=h=1e-3]"
    assert dn.shown("1501 times", ratio, tmp_path)[0] == "1501 times"
    (tmp_path / "t.md").write_text("Intro.\n\n| n | a / b | solved |\n|---|---|---|\n| 10 | 1.15 | 100 % |\n"
                                   "| 100 | 1.02 | 98 % |\n\n| other | n |\n|---|---|\n| 3 | 4 |\n")
    assert dn.shown("1.20", "t.md:a / b[n=10]", tmp_path)[0] == "1.15"
    assert dn.shown("90 %", "t.md:solved[n=10|100]@min", tmp_path)[0] == "98 %"
    assert dn.shown("1", "t.md:other[n=4]", tmp_path)[0] == "3"
    (tmp_path / "g.md").write_text("| law | substeps |\n|---|---|\n| a | 30,009 |\n| b | 1,107,726 (max) |\n")
    assert dn.shown("30009", "g.md:substeps[law=a]", tmp_path)[0] == "30009"     # thousands grouped
    assert dn.shown("1107726", "g.md:substeps[law=b]", tmp_path)[0] == "1107726"
    page = "It took {num}`230 s <r.json:cpu_s>`, within {num}`8.5e-6 m <r.json:err>`.\n"
    text, changed = dn.refresh_text(page, tmp_path)
    assert text == "It took {num}`231 s <r.json:cpu_s>`, within {num}`8.5e-6 m <r.json:err>`.\n"
    assert changed == [(1, "230 s", "231 s")] and dn.refresh_text(text, tmp_path)[1] == []
    fenced = "```text\n{num}`1 s <r.json:cpu_s>`\n```\n\nIt took {num}`230 s <r.json:cpu_s>`.\n"
    text, changed = dn.refresh_text(fenced, tmp_path)        # the example in code stays as written
    assert changed == [(5, "230 s", "231 s")] and text.startswith("```text\n{num}`1 s")


def test_the_site_shows_a_number_from_its_source_and_fails_on_a_stale_one(tmp_path) -> None:
    """The Sphinx role renders the source's number with its provenance as a tooltip, and a
    page whose number disagrees with its source fails a -W build, naming both."""
    pytest.importorskip("myst_parser")
    src = tmp_path / "src"
    src.mkdir()
    (src / "conf.py").write_text(
        "import sys\n"
        f"sys.path.insert(0, {str(ROOT / 'docs' / '_ext')!r})\n"
        "extensions = ['myst_parser', 'docnumbers_role']\n")
    source = "docs/figures/table2_slope_cpu.csv:x_end [m][law [-]=recurdyn,mode [-]=automatic]"

    def build(number: str) -> subprocess.CompletedProcess[str]:
        (src / "index.md").write_text(f"# Page\n\nIt creeps {{num}}`{number} m <{source}>` in 20 s.\n")
        return subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-W", "-q", "-E", str(src),
                               str(tmp_path / "out")], capture_output=True, text=True)

    good = build("0.1005")
    assert good.returncode == 0, good.stderr
    html = (tmp_path / "out" / "index.html").read_text()
    assert re.search(r'<abbr title="docs/figures/table2_slope_cpu.csv: x_end \[m\].*written by python -m '
                     r'cases[^"]*">0.1005 m</abbr>', html), html
    stale = build("0.1006")
    assert stale.returncode != 0 and "the page says '0.1006 m'" in stale.stderr and "'0.1005 m'" in stale.stderr


def test_python_m_cases_writes_the_times_the_guide_quotes(tmp_path, monkeypatch) -> None:
    """A whole run of `python -m cases` (drivers replaced by stand-ins that burn a known share of
    CPU) writes cases.run.json: each driver's wall and CPU time, their sum, and its provenance;
    a run with --only writes none (a part's sum would mislead)."""
    import json
    import time
    sys.path.insert(0, str(ROOT))
    from cases import __main__ as cases_main
    from harness.provenance import provenance_of

    def busy(name: str, argv: list[str]) -> list[Path]:
        end = time.process_time() + 0.2
        while time.process_time() < end:
            pass
        return []

    monkeypatch.setattr(cases_main, "_run_driver", busy)
    cases_main.main(["--outdir", str(tmp_path), "--jobs", "1", "--quiet"])
    numbers = json.loads((tmp_path / "cases.run.json").read_text())["numbers"]
    drivers = [d.name for d in cases_main.DRIVERS if d.kind != "study"]
    assert {f"{d}.cpu_s" for d in drivers} <= set(numbers)
    assert all(numbers[f"{d}.cpu_s"]["value"] >= 0.15 for d in drivers)   # written to 0.1 s
    assert numbers["cpu_s"]["value"] == pytest.approx(sum(numbers[f"{d}.cpu_s"]["value"] for d in drivers),
                                                      abs=0.05 * len(drivers))
    assert provenance_of(tmp_path / "cases.run.json")["command"].startswith("python -m cases")
    (tmp_path / "only").mkdir()
    cases_main.main(["--outdir", str(tmp_path / "only"), "--jobs", "1", "--quiet", "--only", "laws"])
    assert not (tmp_path / "only" / "cases.run.json").exists()


#: The prose of these pages is checked for measured-looking numbers without a source.
NUMBER_PAGES: tuple[str, ...] = tuple(
    p.relative_to(ROOT / "docs").as_posix()
    for p in sorted((ROOT / "docs" / "guide").glob("*.md")) + sorted((ROOT / "docs").glob("*.md"))
    + sorted((ROOT / "docs" / "gallery").glob("*.md")))
#: A number that looks measured: a decimal, an exponent, a grouped integer, or a number with a
#: unit of time, length, speed, force, a factor, a percentage or a count of work.
MEASURED = re.compile(r"(?<![\w.{])(\d+\.\d+(e[-+]?\d+)?|\d+e[-+]?\d+|\d{2,}(,\d{3})+|\d+(\.\d+)?\s?"
                      r"(s|ms|us|µs|x|%|mm|m/s|rad/s|kN|N|evaluations|steps)\b)")
#: Facts every page may write: the paper's parameters and scenes (Table 1 of Yoo & Lee 2008).
PAPER_FACTS: dict[str, str] = {
    "0.35": "mu_s", "0.30": "mu_k", "0.3": "mu_k", "9.81": "g", "300 N": "the belt's spring k [N/m]",
    "1.5": "the belt's speed [m/s]", "10 kg": "the mass", "0.176": "tan 10°", "20 s": "the slope's run",
    "30 s": "the belt's run (ours: the paper gives none)",
}
#: A power of ten (1e-6, 1e5) is a setting chosen (a step, a tolerance, a target), not a
#: measurement, on every page.
SETTING = re.compile(r"1e[-+]?\d+")
#: Facts, not measurements, that a converted page may write as text: {page: {number: why}}.
FACTS: dict[str, dict[str, str]] = {
    "guide/getting-started.md": {
        "3.11": "the Python version required", "0.1": "the paper's words (\"about 0.1 m\")",
        "0.0981": "x_k = mu_k m g / k of the paper's parameters",
    },
    "paper.md": {"3.1": "a section of the paper", "3.2": "a section of the paper"},
    "guide/extending.md": {"8.5": "a journal column's width [cm]"},
    "guide/integrators.md": {
        "4 evaluations": "RK4's stages", "0.04": "Hairer's beta", "0.9": "Hairer's safety factor",
        "0.2": "Hairer's step ratio bound",
        "1442 evaluations": "Hairer's published Arenstorf run (tests/fortran/test_integrators.f90)",
        "240 steps": "Hairer's published Arenstorf run", "0.9940021016": "Hairer's published Arenstorf run",
        "0.89111849e-5": "the Arenstorf run's digits (tests/fortran/test_integrators.f90)",
        "0.8911185692e-5": "Hairer's published value",
        "19670 evaluations": "Hairer's dopri5.f on the same belt (tests/fortran/test_integrators.f90)",
        "3278 steps": "Hairer's dopri5.f on the same belt",
        "2 steps": "calm_steps' default",
    },
    "guide/dop853.md": {
        "12 evaluations": "DOP853's stages a step", "11 evaluations": "DOP853's stages a rejected step",
        "3 evaluations": "DOP853's dense output", "0.01": "a weight of Hairer's error estimate",
        "0.9": "Hairer's safety factor", "0.333": "Hairer's fac1", "6.1": "Hairer's stiffness bound",
        "12.2": "the gfortran version", "23 steps": "Hairer's stiffness stop (tests/fortran/test_integrators.f90)",
        "275 evaluations": "Hairer's stiffness stop",
    },
    "guide/engines.md": {
        "0.01": "a time step named", "0.2": "the box's size [m]", "0.1": "a size, step or threshold chosen",
        "1 mm": "the contact spheres' radius, a threshold chosen",
        "2 s": "Newton's run, chosen", "2.5": "m/(4 k_f) [ms], arithmetic",
        "1 ms": "a time step chosen", "0.17": "the stability bound 2m/(3 · 4 k_f) [ms], arithmetic",
        "0.7265": "the root of mu_d s/sqrt(1 + s^2) = tan 10°",
        "5 ms": "a time step chosen", "10 s": "the rocking runs' length, chosen", "0.7": "a damping ratio chosen",
        "4.0": "MuJoCo's version", "0.5": "solimp's midpoint",
    },
    "guide/results.md": {
        "2.785": "RK4's stability bound on the real axis", "2.828": "RK4's bound on the imaginary axis",
        "0.5164": "2 sqrt(2)/omega of the paper's belt [s], a closed form",
        "5.1643e-4": "the closed-form bound at v_s = 1e-3 m/s [s]",
        "2048 steps": "half the library's interval between looks at the stop flag",
        "10 m/s": "the brake's initial speed", "1000 N": "the brake's largest normal force",
        "0.5": "the brake's ramp [s]", "0.4": "the brake's mu", "5 s": "the runs' length, chosen",
    },
    "benchmarks.md": {
        "1.2": "a goal (at most 1.2 times the reference)", "0.5": "GSL's step-keeping interval",
        "1.05": "a goal (at most 1.05 times the scene code's cost)",
        "1.1": "GSL's step-keeping interval",
        "50,000": "the callgrind run's steps, chosen", "2e6": "the Lotka-Volterra run's steps, chosen",
        "10,000": "the largest chain, chosen",
        "5 s": "the fit's budget",
    },
    "guide/dask.md": {
        "10,000": "chunk_rows' largest default", "100,000": "the benchmark's rows, chosen",
        "0.2": "a duration chosen",
    },
    "guide/chain.md": {
        "0.618": "the golden ratio's fraction", "2 s": "2 s + 1, the band Jacobian's evaluations (s states)",
        "1 evaluations": "2 s + 1, a formula", "10 N": "k_p, chosen",
        "0.2": "a perturbation, duration or precision stated",
        "0.01": "the belt's speed, chosen",
        "0.5": "a duration chosen", "1 s": "a duration chosen",
        "10,000": "a chain size or step count, chosen", "000 s": "1,000 s and 5,000 s runs, chosen",
        "0.05": "the output grid's step, chosen", "10 s": "a duration chosen",
    },
    "reproduction.md": {
        "1 mm": "the error test's threshold, atol/rtol", "0.1": "a scale, threshold or grid named",
        "1.3": "the proposed law's v* [mm/s], a closed form", "5.0": "RecurDyn's v* [mm/s], a closed form",
        "10 ms": "the output grid", "1 ms": "a run's length named", "0.3273": "the proposed law's mu(1.5 m/s)",
        "0.1763": "tan 10°", "5.024": "RecurDyn's v* [mm/s]", "0.1005": "RecurDyn's v* times 20 s [m]",
        "1.279": "the proposed law's v* [mm/s]", "0.02557": "its v* times 20 s [m]",
        "0.11": "the paper's ratio", "0.12": "the paper's ratio", "9.9": "the paper's ratio",
        "10.2": "the paper's ratio", "65 s": "the paper's CPU time", "0.95": "the paper's ratio",
        "1.0": "the paper's ratio", "6 evaluations": "DOPRI5's stages", "6.76": "2 mu_s g cos 10° [m/s^2]",
        "2 steps": "calm_steps' default", "20.0": "t_end in a call", "30.0": "t_end in a call",
        "0.0981": "x_k = mu_k m g / k [m]", "1.147": "the natural period 2 pi sqrt(m/k) [s]",
        "0.963": "v_b - x_k w [m/s]", "0.015": "v_d = 1.5 v_s [m/s]", "0.74": "(1 + (w h)^2)^(-t/(2h)) at h = 1e-3",
        "0.97": "the same at h = 1e-4", "3.3": "DOPRI5's stability bound", "1.1e6": "d mu/dv at 1e-6 v_s [1/s]",
        "5e4": "d mu/dv at 1e-6 m/s [1/s]", "5.48": "sqrt(k/m) [1/s]", "0.25": "galpha_root's constant",
        "0.009": "galpha_root's constant", "0.5": "rho_inf chosen", "0.9": "rho_inf chosen",
        "4e-5": "galpha_root's constant", "5e-3": "w h at h = 1e-3", "0.99": "a tolerance chosen",
        "2.785": "RK4's stability bound", "5.1": "1/(g cos 10° ln(a) (mu_s - mu_k)) [s]",
    },
    "guide/choosing-h.md": {
        "2.785": "RK4's stability bound on the real axis", "3.3": "DOPRI5's stability bound",
        "0.4": "the advice (h <= 0.4 v_s)", "0.5": "the advice (h_min < 0.5 v_s), rho_inf chosen",
        "1.45": "the map's ratio between step sizes, chosen", "1.8": "10^(1/4), arithmetic",
        "2.2e-14": "100 eps, the library's rule", "3 evaluations": "RADAU5's stages a Newton iteration",
        "1 s": "a duration chosen",
    },
    "guide/python-api.md": {
        "4096 steps": "the library's interval between looks at the stop flag",
    },
    "gallery/belt-2dof.md": {
        "0.2": "the belt's speed [m/s]", "400 N": "a spring's stiffness [N/m]", "250 N": "a spring's stiffness [N/m]",
        "100 N": "the coupling spring's stiffness [N/m]", "0.4": "mu_s", "0.25": "mu_k", "0.05": "v_s [m/s]",
        "10 s": "the runs' length, chosen", "6 s": "the measures' window, chosen",
        "1 mm": "the stick threshold [mm/s], chosen", "0.1": "a width v_eps [mm/s], chosen",
        "0.01": "a width v_eps [mm/s], chosen",
    },
    "gallery/coupled-clutches.md": {
        "10 rad/s": "J1's initial speed (CoupledClutches.mo)", "20 N": "fn_max (CoupledClutches.mo)",
        "0.5": "mu_pos's coefficient, Modelica's output interval [ms]", "1.1": "peak (Clutch.mo)",
        "0.2": "clutch 1's frequency [Hz] (CoupledClutches.mo)", "0.4": "clutch 2's step time [s] (CoupledClutches.mo)",
        "0.9": "clutch 3's step time [s] (CoupledClutches.mo)", "0.55": "mu_s = peak mu_k, arithmetic",
        "2020x": "the Dymola version of the reference", "2.5": "the comparison grid [ms], 1.5 s / 600",
        "1.25": "the zero of cos(2 pi 0.2 t) [s], a closed form",
    },
    "gallery/den-hartog.md": {
        "1 N": "k = 1 N/m and P0 = 1 N, the problem's units", "0.1": "a friction ratio F/P0, chosen",
    },
    "gallery/friction-damper-frame.md": {
        "4.0": "the records' licence, CC BY-SA 4.0", "0.5": "the frame's natural period [s], chosen",
        "0.32": "El Centro 1940 NS's peak [g], of the record", "2 ms": "the output grid, chosen",
        "8 s": "a test's run, chosen", "4 s": "a test's run, chosen",
        "14 kN": "a bound of the test (8 to 14 kN)", "20 mm": "a bound of the test (1 to 20 mm)",
    },
    "gallery/steady-states.md": {
        "0.2": "the belt branch's lowest speed [m/s], chosen", "2 m/s": "the belt branch's highest speed, chosen",
        "0.9": "the highest frequency ratio below resonance, chosen", "1.2": "the lowest above it, chosen",
        "0.5": "a friction ratio F/P0 chosen; the damper law's v_s [m/s]", "0.7": "a friction ratio F/P0, chosen",
        "0.1": "the damped belt's speed and v_s [m/s], chosen", "0.4": "mu_s; the damper's c [N s/m], chosen",
        "0.8": "the Hopf branch's start, 0.8 c_H, chosen", "4 N": "the damper's spring [N/m]",
        "10 N": "the damper's forcing amplitude",
    },
    "gallery/stacked-blocks.md": {
        "100 N": "block A's spring [N/m]", "0.2": "the belt's speed [m/s], B's mu_k", "0.5": "mu_s, B's mass [kg]",
        "40 N": "block B's spring [N/m]", "140 N": "100 + 40 N/m, arithmetic", "0.25": "B's mu_s",
        "3 s": "the runs' length, chosen",
    },
    "guide/advisor.md": {
        "0.0": "advise's defaults x0 and v0", "10 s": "t_end of the example, chosen",
        "0.0392177525": "x_k (1 - cos w t) at 10 s [m], a closed form", "000 steps": "the probe's 2,000 steps, a limit",
        "0.5": "rho's cap, a setting; an initial speed [m/s]", "0.8": "the stability bound's safety factor; v_b [m/s]",
        "2.785": "RK4's stability bound on the real axis", "5 mm": "v_s = 5 mm/s of the example",
    },
    "guide/fortran-c.md": {
        "1.1": "meson's version required", "10 rad/s": "the flywheel's initial speed",
        "50 N": "the clutch's normal force", "0.1": "the time the force is applied [s]",
        "3 rad/s": "10/3 rad/s, the closed form's common speed", "1 s": "the run's end, chosen",
    },
    "guide/models.md": {
        "0.4": "the clutch's engagement time [s], a parameter of the example",
        "0.2": "mu_s in the example of an error message", "5.0": "the normal force in the example of a warning",
        "473 x": "the one-body form's force k Omega t (473 x 5 t), arithmetic",
        "5 rad/s": "the surface's speed, chosen", "0.8": "mu_s, chosen", "0.5": "mu_k, an initial speed, chosen",
        "8 s": "the run's length, chosen", "10 rad/s": "the slip scale 5 + 5 rad/s, arithmetic",
        "0.1": "the time the box's friction engages [s], chosen", "50 N": "a spring's stiffness [N/m]",
        "80 N": "a spring's stiffness [N/m]", "4 N": "the force's step", "5 N": "a normal force",
        "1 s": "a run's length, chosen", "200,000": "the adaptive methods' step budget, chosen",
        "2.9": "w h, chosen beyond RK4's stability bound",
    },
    "guide/friction-laws.md": {
        "0.01": "v_s shared by the laws [m/s]", "0.4": "sigma2 of the 1995 paper [N s/m]; the brake's mu",
        "316 rad/s": "sqrt(sigma0/m), the bristle frequency, a closed form", "0.5": "the bristle damping "
        "ratio, a closed form; the brake's ramp [s]", "10 m/s": "the brake's initial speed",
        "1000 N": "the brake's largest normal force", "100 s": "the brake's run, chosen",
        "1.0e-3": "Karnopp's dv [m/s], chosen", "0.04077": "LuGre's default sigma2 = 0.4/9.81 [s/m]",
        "408 N": "sigma2 v N at 10 m/s, arithmetic", "400 N": "mu N, arithmetic", "8.667": "26/3 [m], a closed form",
        "1.73e-5": "tan(theta)/sigma0 [m], a closed form", "0.37245": "the exact Coulomb cycle's x_max [m], a closed form",
        "0.17625": "its x_min [m], a closed form", "1.14717": "its period [s], a closed form",
        "0.200": "g sigma2/2 [1/s], a closed form", "0.0981": "x_k = mu_k m g / k [m]",
        "0.537": "x_k w [m/s], a closed form", "5e4": "sigma0 |v| / g(v) at 1.5 m/s [1/s], a closed form",
        "2.785": "RK4's stability bound on the real axis", "2.7e-5": "2.785 mu_k / (sigma0 v_rel,max) [s], a closed form",
        "3.0": "2 v_b [m/s], the largest relative speed",
        "10 s": "the study's belt runs, chosen",
    },
    "guide/exact-stick.md": {
        "4 s": "a run's length, chosen", "50 N": "a spring's stiffness [N/m], chosen", "0.8": "a belt speed [m/s], chosen",
        "4e-3": "the largest step tried [s]", "5e-4": "the smallest step tried [s]",
        "1 ms": "a step chosen", "0.537315": "a belt speed chosen just below the grazing one [m/s]",
        "0.5373158": "the first slip arc's largest speed [m/s], a closed form", "10 N": "a normal force, chosen",
        "5 N": "half of it, arithmetic", "200 N": "block A's spring [N/m]", "60 N": "block B's spring [N/m]",
        "30 N": "block C's spring [N/m]", "0.5": "C's mass [kg], a normal force's factor, mu_s",
        "3.5": "A's normal force factor (3.5 g N)", "0.4": "mu_s of A-B", "0.2": "mu_k of B-C",
        "5 s": "a run's length, chosen", "2 s": "the stack's run, chosen", "2 m/s": "(b)'s initial speed",
        "1.674": "(b)'s x_stop [m], a closed form", "0.1": "(c)'s belt speed [m/s]",
        "6 s": "the runs' length, chosen", "5 ms": "the output grid, chosen",
    },
    "guide/implicit-nonsmooth.md": {
        "0.05": "a step chosen [s]; the test's tolerance on an order", "0.5": "a step [s], rho_inf or mu_s chosen",
        "3 m/s": "an initial speed chosen", "10 s": "the chain's run, chosen", "2e-3": "a step chosen [s]",
        "5e-4": "a step chosen [s]", "2.5e-4": "a step chosen [s]", "1.25e-4": "a step chosen [s]",
        "0.6": "mu_k or mu_s chosen", "0.7": "mu_s chosen", "2 m/s": "the initial speed chosen",
        "50 N": "the belt's spring [N/m], chosen", "0.2": "the belt's speed [m/s], chosen",
        "1.6017": "the Coulomb cycle's period P [s], a closed form", "3.2": "the run's length in periods, chosen",
        "100 N": "a spring [N/m], chosen", "0.4": "mu_k chosen", "0.01": "the paper's v_s [m/s]",
        "2 s": "a run's length, chosen", "1 s": "a run's length, chosen",
        "2.2e-16": "the spacing of floats at 1.5, eps times 1.5 rounded down to a power of two",
    },
    "guide/identification.md": {
        "0.25": "the data set's lowest frequency [Hz]", "12.7": "the data set's smallest amplitude [mm], 0.5 in",
        "38.1": "its largest [mm], 1.5 in", "4.0": "the records' licence, CC BY-SA 4.0",
        "1 N": "the normal force a fit sets when none is given", "0.999": "identify.Z_BA_RATIO_MAX, a setting",
        "0.999999": "a z_ba_ratio tried",
        "0.5": "a record's frequency [Hz], a default (min_fraction, settle) or a setting named",
        "10 N": "the synthetic records' noise, chosen", "0.975": "the t quantile's probability",
        "2 s": "t(0.975, n - k)^2 s^2, an exponent and the residual variance",
        "0.1": "the probe's step fraction; min_correl's default", "0.45": "identify.BACKLASH_GRID's widest, a setting",
        "5 s": "the benchmark's budget, a setting", "0.05": "a test's tolerance; v_tol's default",
        "3e-3": "a diff_step tried", "1.0": "the bad value in a message shown", "0.0": "a zero force in a message shown",
        "1000 N": "a synthetic record's mu_k, chosen", "4e5": "a synthetic record's sigma0 [N/m], chosen",
        "10 mm": "a synthetic record's amplitude", "4 mm": "a synthetic record's amplitude",
        "20 mm": "a synthetic amplitude; the staircase's step travel, chosen",
        "2 kN": "the synthetic force's range, 2 mu_k", "1.96": "the normal quantile z(0.975)",
        "0.8": "the AR(1) noise's rho, chosen; the decimation filter's cut-off, a setting",
        "50 N": "the noise on the staircase, chosen", "2 N": "the noise on the presliding records, chosen",
        "5 N": "the example's noise on the staircase; a test's bound", "0.005": "the synthetic truth's v_s [m/s]",
        "2e6": "the synthetic truth's sigma0 [N/m]", "0.75": "the presliding length mu_s/sigma0 [mm], a closed form",
        "40 N": "a synthetic load cell's offset, chosen", "0.02": "a synthetic drift [1/s], chosen",
        "25 N": "a synthetic load cell's offset (a test)", "3 N": "a test's bound",
        # measured, by runs of hundreds of fits too long to repeat for the docs: recorded where they ran
        "20,000": "the yardstick's draws (a run recorded in tests/test_identify.py, not in a results file)",
        "94.8": "that run's coverage, least", "95.3": "that run's coverage, most",
        "1.07": "the profiles' cost over Wald's, static laws: the coverage runs of both kinds (650 fits), "
                "recorded before the results files, too long to rerun in a session",
        "1.63": "the same run", "2.1": "the same run, LuGre", "175 evaluations": "the same run, LuGre",
    },
    "guide/prescribed-motion.md": {
        "1.0": "the signature's defaults (normal_force, asymmetry)", "0.0": "the signature's default backlash",
        "2e-7": "the bound tests/test_prescribed.py asserts", "5e-7": "the bound tests/test_prescribed.py asserts",
        "0.6": "a Dahl alpha tested", "2.5": "a Dahl alpha tested", "1 mm": "the sine's amplitude, chosen",
        "2 s": "the benchmark's run, chosen",
    },
}
#: Pages whose numbers are not yet read from their sources: this list may only shrink.
NOT_YET_CONVERTED: frozenset[str] = frozenset()
TABLE_BLOCK = re.compile(r"<!-- table: .*?<!-- end table -->", re.S)


def prose_lines(text: str, raw: bool = False) -> list[tuple[int, str]]:
    """(line number, text) of a Markdown page's prose: outside fenced code, tables (a row, or a
    generated table between its markers) and HTML comments; unless `raw`, inline code, roles
    such as {num}`...`, and math spans blanked."""
    text = TABLE_BLOCK.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    text = re.sub(r"<!--.*?-->", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    out, fence = [], None
    for number, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        mark = re.match(r"(`{3,}|~{3,})", s)
        if mark and (fence is None or s.startswith(fence)):
            fence = None if fence else mark.group(1)
            continue
        if fence or s.startswith("|"):
            continue
        if raw:
            out.append((number, line))
            continue
        s = re.sub(r"\{[a-z-]+\}`[^`]*`", "", s)
        s = re.sub(r"`[^`]*`", "", s)
        s = re.sub(r"\$[^$]*\$", "", s)
        out.append((number, s))
    return out


def bare_numbers(page: str) -> list[tuple[int, str]]:
    """(line, number) of the measured-looking numbers of docs/`page` without a source that are
    not among its FACTS."""
    facts = PAPER_FACTS | FACTS.get(page, {})
    return [(n, m.group(0)) for n, line in prose_lines((ROOT / "docs" / page).read_text())
            for m in MEASURED.finditer(line) if m.group(0) not in facts and not SETTING.fullmatch(m.group(0))]


def test_the_number_checker_tells_a_measurement_from_a_source() -> None:
    text = ("It took 231 s and {num}`231 s <a.json:b>`; `1.5 s` is code.\n| 2.5 s | a table |\n"
            "```python\nprint(3.5)\n```\n<!-- table: x.csv\n-->\nMachine: 4.5 s\n<!-- end table -->\n"
            "$h = 0.5$ and 1e-3 and 12 evaluations\n")
    found = [m.group(0) for _, line in prose_lines(text) for m in MEASURED.finditer(line)]
    assert found == ["231 s", "1e-3", "12 evaluations"]


@pytest.mark.parametrize("page", NUMBER_PAGES)
def test_measured_numbers_in_the_docs_come_from_their_sources(page: str) -> None:
    """A converted page writes every measured number as {num}`TEXT <SOURCE>` (its value then
    checked against the source by test_doc_tables_agree_with_their_results_files); only the
    facts of FACTS stay as text. A page of NOT_YET_CONVERTED must still need its place there."""
    bare = bare_numbers(page)
    if page in NOT_YET_CONVERTED:
        assert bare, f"docs/{page} has no bare measured number any more: remove it from NOT_YET_CONVERTED"
    else:
        assert not bare, (f"docs/{page}: numbers without a source (write {{num}}`TEXT <PATH:KEY>`, "
                          f"tools/docnumbers.py, or add a fact to FACTS): {bare}")


def test_the_lists_name_only_what_exists() -> None:
    """NOT_YET_CONVERTED and FACTS name pages that exist, and each fact is still on its page."""
    assert NOT_YET_CONVERTED <= set(NUMBER_PAGES), NOT_YET_CONVERTED - set(NUMBER_PAGES)
    assert set(FACTS) <= set(NUMBER_PAGES) - NOT_YET_CONVERTED
    for page, facts in FACTS.items():
        found = {m.group(0) for _, line in prose_lines((ROOT / "docs" / page).read_text())
                 for m in MEASURED.finditer(line)}
        assert set(facts) <= found, f"docs/{page}: facts no longer on the page: {set(facts) - found}"


# ---------------------------------------------------------------- the sources' form: no history, no long lines
MARKDOWN: tuple[Path, ...] = (ROOT / "README.md", *(
    p for p in sorted((ROOT / "docs").rglob("*.md")) if "figures" not in p.relative_to(ROOT / "docs").parts))
MAX_LINE: int = 400


def test_the_docs_speak_of_the_package_not_of_its_history() -> None:
    """No page names an issue of the project ("issue 31"): a reader needs what the package does."""
    named = {p.relative_to(ROOT).as_posix(): re.findall(r"\bissues? #?\d+", p.read_text(), re.I)
             for p in MARKDOWN}
    found = {page: hits for page, hits in named.items() if hits}
    assert not found, found


def test_no_paragraph_is_one_long_line() -> None:
    """Markdown prose is wrapped: no line of prose over MAX_LINE characters (tables, code and
    generated tables excepted), so that a change shows as a readable diff."""
    long = [f"{p.relative_to(ROOT).as_posix()}:{n} ({len(line)} characters)"
            for p in MARKDOWN for n, line in prose_lines(p.read_text(), raw=True) if len(line) > MAX_LINE]
    assert not long, long


if __name__ == "__main__":
    print("\n".join(all_undocumented()) or "every public entity is documented")


def test_results_name_no_path_of_the_machine_that_made_them() -> None:
    """Every committed provenance record (docs/figures, benchmarks/results) gives its command as a
    reader can type it in a clone: no absolute path of the machine that ran it (a run into a
    temporary directory copied in by hand would show one)."""
    records = sorted((ROOT / "docs" / "figures").glob("*.provenance.json")) \
        + sorted((ROOT / "benchmarks" / "results").glob("*.provenance.json"))
    assert records
    bad = []
    for path in records:
        for run in json.loads(path.read_text())["runs"]:
            if re.search(r"(^|[\s=])/(tmp|work|home|root|usr)/", run["command"]):
                bad.append(f"{path.relative_to(ROOT)}: {run['command']}")
    assert not bad, "\n".join(bad)


def test_a_path_of_this_machine_is_written_as_its_placeholder(tmp_path, monkeypatch) -> None:
    """A command whose argument is a path of this machine (the presets benchmark's --base SITE)
    is recorded with the placeholder the caller names, whichever way the command was started."""
    from harness.provenance import command_line, write_provenance
    site = str(tmp_path / "base_site")
    monkeypatch.setattr(sys, "argv", [str(ROOT / "benchmarks" / "__main__.py"), "--presets", "--base", site])
    assert command_line("benchmarks", None, {site: "SITE"}) == "python -m benchmarks --presets --base SITE"
    assert site in command_line("benchmarks", None)          # without it the path would show
    monkeypatch.setattr(sys, "argv", ["pytest"])
    path = write_provenance(tmp_path, "demo", [], ["--base", site], shown={site: "SITE"})
    assert json.loads(path.read_text())["runs"][0]["command"] == "python -m demo --base SITE"
