"""The source layout: fortran/ in its layer folders, every module built by meson, and the
integrators' specialised kernels as tools/gen_kernels.py writes them from the registry."""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import gen_kernels  # noqa: E402

LAYERS = {"core", "laws", "integrators", "scenes", "presets", "api"}


def test_generated_kernels_are_current():
    """The committed kernel includes are what the generator writes from the registry now."""
    run = subprocess.run([sys.executable, str(ROOT / "tools" / "gen_kernels.py"), "--check"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def test_generated_files_equal_a_fresh_run(tmp_path: Path):
    """The generator run into an empty directory writes every generated file (the kernels'
    includes, the laws' dispatch and meson's list of law sources) equal to the committed one:
    the build never needs the generator, only an edit of the registry does."""
    run = subprocess.run([sys.executable, str(ROOT / "tools" / "gen_kernels.py"), "--outdir", str(tmp_path)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    written = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*") if p.is_file())
    assert written == sorted(["fortran/integrators/stickslip_kernel_instances.inc",
                              "fortran/integrators/stickslip_kernel_dispatch.inc",
                              "fortran/laws/stickslip_laws.f90", "fortran/laws/meson.build"])
    stale = [f for f in written if (tmp_path / f).read_text() != (ROOT / f).read_text()]
    assert not stale, f"stale (run python tools/gen_kernels.py): {stale}"


def test_the_laws_dispatch_follows_law_table():
    """stickslip_laws holds a `use`, a code and a `new_law` case for every LAW_TABLE row in
    order, and every law parameter's specification once; meson compiles every law module."""
    source = gen_kernels.REGISTRY.read_text()
    names = [name for name, _ in gen_kernels.table_entries(source, "LAW_TABLE")]
    shared, rows = gen_kernels.law_entries(source)
    assert [name for name, _ in rows] == names and shared == ["MU_S_SPEC", "MU_K_SPEC", "V_S_SPEC"]
    module = (ROOT / "fortran" / "laws" / "stickslip_laws.f90").read_text()
    assert re.findall(r"^    use stickslip_law_(\w+)", module, re.M) == names
    assert re.findall(r"LAW_(\w+) = (\d+)$", module, re.M) == [(n.upper(), str(i)) for i, n in enumerate(names, 1)]
    assert re.findall(r"allocate\((\w+)_law :: law\)", module) == names
    specs = [c for _, own in rows for c in own]
    assert len(set(specs)) == len(specs) and {"V_D_SPEC", "DV_SPEC", "GMS_C_SPEC"} <= set(specs)


def test_the_laws_generator_names_what_is_missing(tmp_path: Path):
    """A row without its module, or naming a parameter no module declares, stops the generator
    with the law and what is missing."""
    source = gen_kernels.REGISTRY.read_text()
    row = "entry_info('toy', 'mu_k toy_c', 'a toy'), &\n        "
    added = source.replace("entry_info('coulomb',", row + "entry_info('coulomb',", 1)
    with pytest.raises(SystemExit, match="law 'toy' of LAW_TABLE has no module file"):
        gen_kernels.law_entries(added, laws=tmp_path)
    laws = tmp_path / "laws"
    shutil.copytree(gen_kernels.LAWS, laws)
    (laws / "stickslip_law_toy.f90").write_text("module stickslip_law_toy\n"
                                                "    type, extends(friction_law) :: toy_law\n")
    with pytest.raises(SystemExit, match="law 'toy' reads toy_c, which no law module declares"):
        gen_kernels.law_entries(added, laws=laws)
    (laws / "stickslip_law_toy.f90").write_text(
        "module stickslip_law_toy\n    type, extends(friction_law) :: toy_law\n"
        "    type(param_spec), parameter, public :: TOY_MU = param_spec(name='mu_s', default=1.0_dp)\n")
    with pytest.raises(SystemExit, match="declares mu_s, which MU_S_SPEC declares already"):
        gen_kernels.law_entries(added, laws=laws)


def test_kernels_follow_the_registry_flags():
    """The kernels are those of the registry's kernel=.true. laws, no more, each on the model
    structure of one body with one contact (no scene type): unmarking a law drops its kernels
    and its dispatch case; the generic kernel always stays."""
    source = gen_kernels.REGISTRY.read_text()
    assert gen_kernels.kernel_entries(source, "LAW_TABLE") == ["coulomb", "recurdyn", "proposed", "stribeck"]
    assert gen_kernels.kernel_entries(source, "SCENE_TABLE") == []
    edited = re.sub(r"('stribeck'.*?), kernel=\.true\.\)", r"\1)", source, count=1, flags=re.S)
    laws = gen_kernels.kernel_entries(edited, "LAW_TABLE")
    assert laws == ["coulomb", "recurdyn", "proposed"]
    text = gen_kernels.instances(laws) + gen_kernels.dispatch(laws)
    assert "stribeck" not in text and "kernel_proposed" in text and "generic_kernel" in text
    assert "type(one_contact_model)" in text and "_scene" not in text


def test_every_module_is_in_a_layer_and_built():
    """No Fortran source outside the layer folders, and meson.build compiles every module."""
    assert not list((ROOT / "fortran").glob("*.f90")) and not list((ROOT / "fortran").glob("*.inc"))
    assert {p.name for p in (ROOT / "fortran").iterdir() if p.is_dir()} == LAYERS
    meson = (ROOT / "meson.build").read_text()
    listed = set(re.findall(r"'(fortran/\w+/stickslip\w*\.f90)'", meson))
    # the laws' sources: fortran/laws/meson.build, written from the registry (tools/gen_kernels.py)
    assert "subdir('fortran/laws')" in meson and "+ law_src +" in meson
    listed |= {f"fortran/laws/{f}" for f in re.findall(r"'(stickslip\w*\.f90)'",
                                                       (ROOT / "fortran" / "laws" / "meson.build").read_text())}
    on_disk = {str(p.relative_to(ROOT)) for p in (ROOT / "fortran").glob("*/*.f90")}
    assert listed == on_disk


# --- Fortran: `use` runs one way through the layers -------------------------------------------
#: The layers of the Fortran library, in order: a module uses only modules of its own layer and
#: of those before it. A module's layer is its folder's (scenes/ holds the model layer; the
#: scenes themselves are presets, fortran/presets/, built on the model).
FORTRAN_LAYERS: tuple[str, ...] = ("core", "laws", "contact", "model", "integrators", "presets", "api")
FOLDER_LAYER: dict[str, str] = {"core": "core", "laws": "laws", "contact": "contact", "scenes": "model",
                                "model": "model", "integrators": "integrators", "presets": "presets",
                                "api": "api"}
#: Today's uses against the layers, each with the reason it is still there: (module, used).
#: A new violation fails; so does an entry here that is no longer needed (remove it).
KNOWN_LAYER_EXCEPTIONS: dict[tuple[str, str], str] = {
}
USE = re.compile(r"^\s*use\s*(?:,\s*\w+\s*)?(?:::\s*)?(stickslip_\w+)", re.I | re.M)
MODULE = re.compile(r"^\s*module\s+(stickslip_\w+)\s*$", re.I | re.M)


def fortran_layer(path: Path) -> dict[str, tuple[str, set[str]]]:
    """Module -> (its layer, the stickslip modules it uses) for every module under `path`."""
    out: dict[str, tuple[str, set[str]]] = {}
    for f in sorted(path.glob("*/*.f90")):
        text = f.read_text()
        for name in MODULE.findall(text):
            layer = FOLDER_LAYER[f.parent.name]
            out[name.lower()] = (layer, {u.lower() for u in USE.findall(text)} - {name.lower()})
    return out


def layer_violations(modules: dict[str, tuple[str, set[str]]]) -> set[tuple[str, str]]:
    """(module, used) pairs where the used module is of a later layer than the user."""
    rank = {layer: i for i, layer in enumerate(FORTRAN_LAYERS)}
    return {(m, u) for m, (layer, uses) in modules.items() for u in uses
            if u in modules and rank[modules[u][0]] > rank[layer]}


def test_fortran_use_follows_the_layers():
    """core, laws, contact, model, integrators, presets, api: each uses only those before it,
    apart from today's listed exceptions (and every listed exception is still needed)."""
    modules = fortran_layer(ROOT / "fortran")
    assert {"stickslip_kinds", "stickslip_registry", "stickslip_presets"} <= modules.keys()
    assert modules["stickslip_presets"][0] == "presets" and modules["stickslip_model_system"][0] == "model"
    found = layer_violations(modules)
    new = sorted(found - KNOWN_LAYER_EXCEPTIONS.keys())
    stale = sorted(KNOWN_LAYER_EXCEPTIONS.keys() - found)
    assert not new, "uses against the layers " + " > ".join(FORTRAN_LAYERS) + f": {new}"
    assert not stale, f"no longer used, remove from KNOWN_LAYER_EXCEPTIONS: {stale}"


def test_the_layer_check_finds_a_violation(tmp_path: Path):
    """The reader sees `use, intrinsic`-free uses of every form, and a core module using an
    integrator is a violation."""
    (tmp_path / "core").mkdir()
    (tmp_path / "integrators").mkdir()
    (tmp_path / "core" / "a.f90").write_text("module stickslip_a\n  use stickslip_b, only: x\nend module\n")
    (tmp_path / "integrators" / "b.f90").write_text(
        "module stickslip_b\n  USE :: stickslip_a\n  use stickslip_a\nend module stickslip_b\n")
    modules = fortran_layer(tmp_path)
    assert modules == {"stickslip_a": ("core", {"stickslip_b"}), "stickslip_b": ("integrators", {"stickslip_a"})}
    assert layer_violations(modules) == {("stickslip_a", "stickslip_b")}


# --- Fortran: no procedure over MAX_PROCEDURE_LINES ----------------------------------------------
MAX_PROCEDURE_LINES = 250
#: Generated sources (tools/gen_kernels.py), not measured.
GENERATED: frozenset[str] = frozenset({"stickslip_kernel_instances.inc", "stickslip_kernel_dispatch.inc",
                                       "stickslip_laws.f90"})
#: Today's longer procedures (file, procedure), each being split; any other fails, and so does
#: an entry here that is no longer long (remove it).
LONG_PROCEDURES: dict[tuple[str, str], str] = {
    ("stickslip_fixed_implicit_body.inc", "KERNEL"): "the fixed-step implicit kernel body, to split "
                                                     "with one contact module (issue 41 item 2)",
    ("stickslip_radau5_body.inc", "KERNEL"): "RADAU5's kernel body (Hairer's RADCOR in one piece), to split",
    ("stickslip_dop853_body.inc", "KERNEL"): "DOP853's kernel body, to split with DOPRI5's (their shared "
                                             "driver loop)",
    ("stickslip_dopri5_body.inc", "KERNEL"): "DOPRI5's kernel body, to split with DOP853's",
    ("stickslip_prescribed.f90", "prescribed_motion"): "prescribed motion's law loop, to split per law family",
}
START = re.compile(r"^\s*(?:(?:pure|elemental|impure|recursive|module|non_recursive)\s+|"
                   r"(?:integer|real|logical|complex|character|type|class)\b[^!]*?\s+)*"
                   r"(subroutine|function)\s+(\w+)", re.I)
END = re.compile(r"^\s*end\s*(subroutine|function)\b", re.I)
INTERFACE = re.compile(r"^\s*(abstract\s+)?interface\b", re.I)
END_INTERFACE = re.compile(r"^\s*end\s*interface\b", re.I)


def procedure_lengths(text: str) -> dict[str, int]:
    """Lines of each outermost procedure of `text`, its internal procedures included
    (interface blocks are not procedures)."""
    out: dict[str, int] = {}
    stack: list[tuple[str, int]] = []
    in_interface = False
    for i, line in enumerate(text.splitlines()):
        code = line.split("!", 1)[0]
        if INTERFACE.match(code):
            in_interface = True
        elif END_INTERFACE.match(code):
            in_interface = False
        elif in_interface:
            continue
        elif END.match(code):
            name, first = stack.pop()
            if not stack:
                out[name] = max(out.get(name, 0), i - first + 1)
        elif (m := START.match(code)) and not re.match(r"^\s*end\b", code, re.I):
            stack.append((m.group(2), i))
    return out


def test_no_procedure_is_longer_than_the_limit():
    """No Fortran procedure over MAX_PROCEDURE_LINES lines outside generated code, except
    today's listed ones (each still long)."""
    long: dict[tuple[str, str], int] = {}
    for f in sorted((ROOT / "fortran").glob("*/*")):
        if f.suffix in (".f90", ".inc") and f.name not in GENERATED:
            for name, n in procedure_lengths(f.read_text()).items():
                if n > MAX_PROCEDURE_LINES:
                    long[(f.name, name)] = n
    new = {k: n for k, n in long.items() if k not in LONG_PROCEDURES}
    stale = sorted(LONG_PROCEDURES.keys() - long.keys())
    assert not new, f"procedures over {MAX_PROCEDURE_LINES} lines: {new}"
    assert not stale, f"no longer over {MAX_PROCEDURE_LINES} lines, remove from LONG_PROCEDURES: {stale}"


def test_procedure_lengths_count_internal_procedures():
    text = ("module m\ncontains\n  pure function f(x) result(y)\n    real :: x, y\n    abstract interface\n"
            "      subroutine g()\n      end subroutine g\n    end interface\n    y = h(x)\n  contains\n"
            "    real function h(x)\n      real :: x\n      h = x\n    end function h\n  end function f\n"
            "  subroutine s\n  end subroutine\nend module m\n")
    assert procedure_lengths(text) == {"f": 13, "s": 2}


# --- Python: one shared package, no private cross-package import, no cycle ----------------------
#: The Python packages of the repository: the library, what cases/, benchmarks/ and tools/
#: share (harness/), and those three. harness imports none of the last three.
PY_PACKAGES: dict[str, Path] = {"stickslip": ROOT / "python" / "stickslip", "harness": ROOT / "harness",
                                "cases": ROOT / "cases", "benchmarks": ROOT / "benchmarks", "tools": ROOT / "tools"}


def python_imports(packages: dict[str, Path]) -> dict[str, set[str]]:
    """Module -> every module or name it imports (deferred imports included), read with ast."""
    from test_imports import imported_modules
    graph: dict[str, set[str]] = {}
    for pkg, folder in packages.items():
        for p in sorted(folder.glob("*.py")):
            name = pkg if p.stem == "__init__" else f"{pkg}.{p.stem}"
            graph[name] = imported_modules(p, pkg)
    return graph


def private_imports(graph: dict[str, set[str]]) -> list[str]:
    """'a imports b' where b is a private module or name (a part starting with one '_') of
    another top-level package than a's."""
    def private(name: str) -> bool:
        return any(part.startswith("_") and not part.startswith("__") for part in name.split(".")[1:])
    return sorted(f"{m} imports {i}" for m, imports in graph.items() for i in imports
                  if private(i) and i.split(".")[0] != m.split(".")[0] and i.split(".")[0] in PY_PACKAGES)


def test_python_packages_import_no_private_module_of_another():
    graph = python_imports(PY_PACKAGES)
    assert "harness.files" in graph["cases._common"]                # the graph is read
    assert not private_imports(graph), "\n".join(private_imports(graph))


def test_python_packages_have_no_import_cycle():
    """No cycle among the modules of all five packages (cases/_common.py and _provenance.py
    imported each other), and harness imports nothing of cases/, benchmarks/ or tools/."""
    from test_imports import find_cycle
    graph = python_imports(PY_PACKAGES)
    modules = set(graph)
    # an import of a module of one's own package through its name ("from . import x") runs the
    # package's __init__ first, which is not an edge of a cycle
    edges = {m: {i for i in imports if i in modules and i != m.split(".")[0]} for m, imports in graph.items()}
    assert find_cycle(edges) is None, " -> ".join(find_cycle(edges) or [])
    up = sorted(f"{m} imports {i}" for m in graph if m.startswith("harness")
                for i in graph[m] if i.split(".")[0] in ("cases", "benchmarks", "tools"))
    assert not up, up


def test_the_python_checks_find_what_they_look_for():
    graph = {"benchmarks.run": {"cases._common", "cases.stick", "stickslip.core._private"},
             "cases.stick": {"cases._common", "stickslip.core"}}
    assert private_imports(graph) == ["benchmarks.run imports cases._common",
                                      "benchmarks.run imports stickslip.core._private"]


# --- The extending guide's layout section names what the tree holds ------------------------------
def layout_block() -> str:
    text = (ROOT / "docs" / "guide" / "extending.md").read_text()
    section = text.split("## Layout", 1)[1]
    return section.split("```", 2)[1]


def test_the_guides_layout_names_the_tree():
    """Every top-level folder with tracked files, every Fortran module (by its name after
    stickslip, as the section writes them), every Python module of the package and of
    harness/, and every private module of cases/ appear in the layout section: a file added
    without a line there fails."""
    block = layout_block()
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                             check=True).stdout.split()
    folders = {p.split("/")[0] for p in tracked if "/" in p and not p.startswith(".")}
    missing = [f"{d}/" for d in sorted(folders) if f"{d}/" not in block]
    for f in sorted((ROOT / "fortran").glob("*/*.f90")):
        short = f.stem.removeprefix("stickslip")
        if f.stem not in block and short not in block and not f.stem.startswith("stickslip_law_"):
            missing.append(str(f.relative_to(ROOT)))
    for folder in (ROOT / "python" / "stickslip", ROOT / "harness"):
        missing += [str(p.relative_to(ROOT)) for p in sorted(folder.glob("*.py"))
                    if p.stem != "__init__" and p.stem != "__main__" and p.name not in block]
    missing += [str(p.relative_to(ROOT)) for p in sorted((ROOT / "cases").glob("_*.py"))
                if not p.stem.startswith("__") and p.name not in block]
    assert not missing, f"not in docs/guide/extending.md's layout section: {missing}"


# --- tests/ mirrors the package (tests/README.md) ------------------------------------------------
#: What each file of tests/project/ checks: the house's tests, of no one module (the docs, the
#: figures, the layout, the installed library, fpm, the examples, the benchmarks' driver).
PROJECT_TESTS: dict[str, str] = {
    "test_benchmarks.py": "the benchmark driver's quick run",
    "test_docs.py": "FORD doc comments, the docs site, the generated tables and the guides' numbers",
    "test_examples.py": "every python and sh block of README.md and docs/ runs as written",
    "test_figures.py": "the figure checklist, measured on the committed figures and the CLI's plot",
    "test_fpm.py": "fpm builds and tests the library from the same sources",
    "test_guides.py": "the guides name every registered law, scene and method",
    "test_imports.py": "imports run one way (cases never imports benchmarks; no cycle)",
    "test_install.py": "the installed library, as docs/guide/fortran-c.md shows it",
    "test_layout.py": "the source layout and this test layout",
    "test_run_anywhere.py": "python -m cases from any directory",
}
#: The Fortran modules tested by another module's test file, each the way in to it (a Python
#: module the Fortran module serves, or the module that uses it): Fortran module -> test file.
FORTRAN_TESTED_THROUGH: dict[str, str] = {
    "stickslip_batch": "tests/test_batch.py",
    "stickslip_simulate": "tests/test_core.py",
    "stickslip_user_model": "tests/test_model.py",
    "stickslip_prescribed": "tests/test_prescribed.py",
    "stickslip_signal": "tests/test_signal.py",
    "stickslip_kinds": "tests/fortran/test_stickslip_registry.f90",
    "stickslip_params": "tests/fortran/test_stickslip_registry.f90",
    "stickslip_friction": "tests/fortran/test_laws.f90",
    "stickslip_ode": "tests/fortran/test_integrators_common.f90",
    "stickslip_linalg": "tests/fortran/test_integrators_implicit.f90",
    "stickslip_roots": "tests/fortran/test_stickslip_event_driven.py",
    "stickslip_contact_solver": "tests/fortran/test_stickslip_contact_general.f90",
    "stickslip_lcp": "tests/fortran/test_stickslip_contact_general.f90",
}
#: Files of tests/ that are no test file: the shared fixtures, references several files use and
#: the C and Fortran sources the tests build.
TEST_SUPPORT: frozenset[str] = frozenset({
    "tests/README.md", "tests/conftest.py", "tests/contact_reference.py", "tests/fortran/test_support.f90",
    "tests/c/capi_model_cases.c", "tests/c/capi_orbit_cases.c", "tests/gsl/gsl_reference.c"})
#: The runner of the Fortran unit test programs (tests/fortran/*.f90), each of which has its owner.
FORTRAN_RUNNER = "tests/fortran/test_fortran.py"


def _owner(stem: str, names: set[str]) -> str | None:
    """The longest name n of `names` with stem == "test_" + n or stem starting "test_" + n + "_"."""
    body = stem.removeprefix("test_")
    found = [n for n in names if body == n or body.startswith(n + "_")]
    return max(found, key=len) if found else None


def layout_of_tests(root: Path) -> tuple[dict[str, str], list[str], list[str]]:
    """The test files under root/tests with the module (or layer, gallery, house set) each
    tests, the files that test nothing of the tree ("extra") and the modules without a test
    file ("missing"). The rules, README's and tests/README.md's:

    - python/stickslip/<m>.py: tests/test_<m>.py (__main__.py: tests/test_main.py); a module's
      further files tests/test_<m>_<topic>.py;
    - fortran/<layer>/stickslip_<x>.f90: tests/fortran/test_stickslip_<x>[_<topic>].py or .f90,
      or a file of its layer, tests/fortran/test_<layer>[_<topic>].py or .f90 (tests of several
      modules of the layer: every law, every method), or FORTRAN_TESTED_THROUGH;
    - cases/gallery_<x>.py: tests/cases/test_gallery_<x>.py; another module of cases/ (<x>.py
      or _<x>.py) may have tests/cases/test_cases_<x>[_<topic>].py;
    - the house's tests: tests/project/, the files of PROJECT_TESTS.
    """
    tests = root / "tests"
    py = {p.stem for p in (root / "python" / "stickslip").glob("*.py") if not p.stem.startswith("_")} | {"main"}
    layers = {p.parent.name for p in (root / "fortran").glob("*/stickslip_*.f90")}
    fortran = {p.stem: p.parent.name for p in (root / "fortran").glob("*/stickslip_*.f90")}
    cases = {p.stem.lstrip("_") for p in (root / "cases").glob("*.py") if not p.stem.startswith("__")}
    galleries = {c for c in cases if c.startswith("gallery_")}
    owners: dict[str, str] = {}
    extra: list[str] = []
    for p in sorted(tests.rglob("*")):
        rel = str(p.relative_to(root))
        if p.is_dir() or "__pycache__" in rel or p.suffix == ".pyc" or rel in TEST_SUPPORT or rel == FORTRAN_RUNNER:
            continue
        folder, stem = p.parent.relative_to(tests).as_posix(), p.stem
        owner = None
        if folder == "." and p.suffix == ".py":
            owner = _owner(stem, py)
            owner = owner and f"python/stickslip/{'__main__' if owner == 'main' else owner}.py"
        elif folder == "fortran" and p.suffix in (".py", ".f90"):
            module, layer = _owner(stem, set(fortran)), _owner(stem, layers)
            owner = (module and f"fortran/{fortran[module]}/{module}.f90") or (layer and f"fortran/{layer}/")
        elif folder == "cases" and p.suffix == ".py":
            name = _owner(stem, galleries) or (stem.startswith("test_cases_") and _owner(stem.replace("test_cases_", "test_", 1),
                                                                                            cases - galleries))
            owner = name and next(f"cases/{f.name}" for f in (root / "cases").glob("*.py") if f.stem.lstrip("_") == name)
        elif folder == "project" and p.name in PROJECT_TESTS:
            owner = "the house"
        if owner:
            owners[rel] = owner
        else:
            extra.append(rel)
    covered = set(owners.values())
    missing = [f"tests/test_{m}.py" for m in sorted(py)
               if f"python/stickslip/{'__main__' if m == 'main' else m}.py" not in covered]
    for module, layer in sorted(fortran.items()):
        through = FORTRAN_TESTED_THROUGH.get(module)
        if not ({f"fortran/{layer}/{module}.f90", f"fortran/{layer}/"} & covered
                or (through and through in owners)):
            missing.append(f"tests/fortran/test_{module}.py (or .f90) for fortran/{layer}/{module}.f90")
    missing += [f"tests/cases/test_{g}.py" for g in sorted(galleries) if f"cases/{g}.py" not in covered]
    missing += [f"tests/project/{n}" for n in sorted(PROJECT_TESTS) if not (tests / "project" / n).exists()]
    return owners, extra, missing


def test_every_module_has_its_test_file_and_every_test_file_a_module():
    """The layout of tests/ (layout_of_tests's rules): a module without a test file or a test file
    that maps to no module fails, with its name; no two test files share a name (pytest
    imports them by name)."""
    owners, extra, missing = layout_of_tests(ROOT)
    assert "tests/test_core.py" in owners and "tests/fortran/test_stickslip_presets_chain.py" in owners
    assert not extra, f"test files that map to no module (tests/README.md gives the rules): {extra}"
    assert not missing, f"modules without their test file: {missing}"
    names = [Path(p).name for p in owners if p.endswith(".py")]
    assert len(names) == len(set(names)), sorted(n for n in names if names.count(n) > 1)
    stale = sorted(m for m, f in FORTRAN_TESTED_THROUGH.items() if not (ROOT / f).exists())
    assert not stale, f"FORTRAN_TESTED_THROUGH names absent files: {stale}"


def test_the_test_layout_check_finds_a_missing_and_an_extra_file(tmp_path: Path):
    """On a small tree: a Python module without tests/test_<m>.py, a Fortran module of a layer
    without a file, and a test file named after nothing are each reported by name."""
    for rel in ("python/stickslip/core.py", "python/stickslip/model.py", "python/stickslip/_wrap.py",
                "fortran/laws/stickslip_law_dahl.f90", "fortran/integrators/stickslip_rk4.f90",
                "cases/gallery_frame.py", "cases/_common.py", "tests/test_core.py", "tests/test_core_errors.py",
                "tests/fortran/test_laws.f90", "tests/test_gallery1.py", "tests/cases/test_cases_common.py",
                *(f"tests/project/{n}" for n in PROJECT_TESTS)):
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text("")
    owners, extra, missing = layout_of_tests(tmp_path)
    assert owners["tests/test_core_errors.py"] == "python/stickslip/core.py"
    assert owners["tests/fortran/test_laws.f90"] == "fortran/laws/"
    assert owners["tests/cases/test_cases_common.py"] == "cases/_common.py"
    assert extra == ["tests/test_gallery1.py"]
    assert missing == ["tests/test_main.py", "tests/test_model.py",
                       "tests/fortran/test_stickslip_rk4.py (or .f90) for fortran/integrators/stickslip_rk4.f90",
                       "tests/cases/test_gallery_frame.py"]
