"""The test session is long work: it runs thousands of steady states, so it uses the compiled
kernels as a sweep or a study does (`rotarydryer._jit.long_runs`; the auto mode of
``ROTARYDRYER_JIT``). The command-line tests run one-off commands in their own processes, which
take the NumPy path as a user's one-off command does: both paths are exercised."""

from rotarydryer import _jit

_jit.long_runs()
