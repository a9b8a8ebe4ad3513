"""Shared by the e2e tests: counting assertions and the closing 'N passed, N failed' line."""
import sys


class Checks:
    def __init__(self):
        self.passed, self.failures = 0, []

    def expect(self, cond, msg):
        if cond:
            self.passed += 1
        else:
            self.failures.append(msg)
            print("FAIL:", msg)
        return cond

    def finish(self):
        print(f"{self.passed} passed, {len(self.failures)} failed")
        sys.exit(1 if self.failures else 0)
