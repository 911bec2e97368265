"""A message list that calls back into an instance from inside the FMU's logger (re-entry tests:
robust_worker.py, adversarial_reentry.py)."""


class Hook(list):
    """A message list that runs `action` after a message arrives (from inside the FMU's logger
    call), for the first `times` messages, and keeps what the action returned."""

    def __init__(self, action, times=1):
        super().__init__()
        self.action, self.times, self.results = action, times, []

    def append(self, m):
        super().append(m)
        if self.action is not None and len(self.results) < self.times:
            k = len(self.results)
            self.results.append(None)  # taken before the action runs: nested messages count too
            self.results[k] = self.action()
