"""Command-line pieces shared by cases/, benchmarks/ and tools/: argparse types with the
accepted range in their messages, the --help text from a module's docstring, and --outdir under
the one rule for output paths (stickslip.outputs): missing directories are created, an
unwritable one is refused while the arguments are parsed, before any work, with the path and
the reason.
"""
from __future__ import annotations

import argparse
import inspect
import math
import os
from pathlib import Path
from typing import Callable

from stickslip.outputs import output_problem

__all__ = ["float_in", "int_at_least", "cli_description", "output_dir", "add_outdir", "check_writable"]


def float_in(low: float, high: float = math.inf, *, low_closed: bool = False,
             what: str | None = None) -> Callable[[str], float]:
    """argparse type: a finite float in (low, high), or [low, high) with low_closed. argparse
    names the option in its error; the message states the accepted range (`what` replaces the
    printed lower bound, e.g. "100 eps = 2.2e-14")."""
    lo = what or f"{low:g}"
    accepted = (f"> {lo}" if not low_closed else f">= {lo}") if math.isinf(high) else \
        f"in {'[' if low_closed else '('}{lo}, {high:g})"

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
        ok = math.isfinite(value) and value < high and (value >= low if low_closed else value > low)
        if not ok:
            raise argparse.ArgumentTypeError(f"must be finite and {accepted}, got {text}")
        return value

    parse.__name__ = "float"        # argparse's "invalid float value" wording for other errors
    return parse


def int_at_least(minimum: int) -> Callable[[str], int]:
    """argparse type: an integer >= minimum."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be an integer >= {minimum}, got {text}")
        return value

    parse.__name__ = "int"
    return parse



def cli_description(doc: str) -> str:
    """The --help description of a command from its module docstring: the first paragraph and,
    when it announces them with a colon, the paragraphs that follow (a usage block, a list),
    whole; reST's "::" shown as ":". Use with argparse.RawDescriptionHelpFormatter."""
    out = []
    for paragraph in inspect.cleandoc(doc).split("\n\n"):
        out.append(paragraph.replace("::\n", ":\n").rstrip(":") + (":" if paragraph.rstrip().endswith(":") else ""))
        if not paragraph.rstrip().endswith(":"):
            break
    return "\n\n".join(out)


def output_dir(text: str) -> Path:
    """argparse type of --outdir: the directory, created with its parents if missing, or an
    argparse error naming it and why it cannot be written (stickslip.outputs.output_problem)."""
    problem = output_problem(text, directory=True)
    if problem:
        raise argparse.ArgumentTypeError(problem)
    return Path(text)


output_dir.__name__ = "directory"


def add_outdir(parser: argparse.ArgumentParser, default: str | None = "out",
               help: str = "directory for CSV, PNG and Markdown files (default: out/)") -> None:
    """Add --outdir to `parser` under the rule of every command (`output_dir`, checked as the
    arguments are parsed: the default too, when it is used)."""
    parser.add_argument("--outdir", type=output_dir, default=default, help=help)


def check_writable(parser: argparse.ArgumentParser, outdir: str | os.PathLike[str]) -> None:
    """End the command with a usage error (exit 2, no traceback) if `outdir`, a directory
    derived after parsing (e.g. a subdirectory per parameter set), cannot be written."""
    problem = output_problem(outdir, directory=True)
    if problem:
        parser.error(f"argument --outdir: {problem}")
