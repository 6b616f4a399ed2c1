"""The tests/docs scripts' verdict: checks are (good, what) pairs; every failed one is printed."""


def verdict(checks):
    """Prints 'FAILED: what' for each failed check; the exit status (1 if any failed)."""
    failed = [what for good, what in checks if not good]
    for what in failed:
        print("FAILED: " + what)
    return 1 if failed else 0
