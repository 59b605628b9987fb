"""What cases/, benchmarks/ and tools/ share: results files written whole (`files`), command
lines and the rule for output paths (`cli`), where a results file came from (`provenance`),
timing (`timing`) and the style of every figure (`style`).

It imports the library (stickslip) and nothing of cases/, benchmarks/ or tools/, which import
it (tests/project/test_layout.py).
"""
