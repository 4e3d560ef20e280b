"""The one tally the tests/check_*.py scripts share: `check` records a failed condition and prints it;
`finish` prints the count and exits non-zero when any failed (ctest reads the exit code)."""
import sys

failures = []
checks = [0]


def check(condition, what):
    checks[0] += 1
    if not condition:
        failures.append(what)
        print("FAILED:", what)
    return bool(condition)


def finish(prefix=""):
    print(f"{prefix}{checks[0]} checks, {len(failures)} failure(s)")
    sys.exit(1 if failures else 0)
