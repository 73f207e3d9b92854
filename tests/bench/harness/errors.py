"""Error evaluators of the work-precision benchmarks: a benchmark names one in `error:` and gives its numbers in
`variables:`. The measures themselves are the compare tool's (tools/stickslip_compare/errors.py, one implementation
for both); the norm of each is stated there and in docs/benchmarks.md."""
import os
import sys

from declarations import ROOT, DeclarationError

sys.path.insert(0, os.path.join(ROOT, "tools"))
from stickslip_compare.errors import (EVALUATORS, PROFILE_RANGE, ErrorMeasureError,  # noqa: E402,F401
                                      reference_positions)


def hertz_profile(results, bench, run, reference):
    return EVALUATORS["hertz_profile"](results, bench.variables, reference)


def evaluate(bench, results, run, reference):
    if bench.error not in EVALUATORS:
        raise DeclarationError("%s: error: unknown evaluator %r (known: %s)" % (bench.path, bench.error,
                                                                               ", ".join(sorted(EVALUATORS))))
    try:
        return EVALUATORS[bench.error](results, bench.variables, reference)
    except ErrorMeasureError as e:
        raise DeclarationError("%s: %s" % (bench.path, e))
