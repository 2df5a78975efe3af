"""Small helpers shared by the program-level tests: checks that print the
value, the expected value and the tolerance, and a closing count line."""
import sys

_checks = {"passed": 0, "failed": 0}


def check_close(what, value, expected, tolerance, relative=True):
    error = abs(value - expected)
    allowed = tolerance * abs(expected) if relative else tolerance
    ok = value == value and error <= allowed  # value == value: not NaN
    _checks["passed" if ok else "failed"] += 1
    print(f"{'ok  ' if ok else 'FAIL'} {what}: {value:.10g} expected {expected:.10g} "
          f"(error {error:.3g}, allowed {allowed:.3g})")
    return ok


def check_true(what, condition):
    _checks["passed" if condition else "failed"] += 1
    print(f"{'ok  ' if condition else 'FAIL'} {what}")
    return condition


def report():
    print(f"{_checks['passed']} passed, {_checks['failed']} failed")
    sys.exit(0 if _checks["failed"] == 0 else 1)
