"""The test session is long work: it runs thousands of steady states, so it uses the compiled
kernels as a sweep or a study does (`rotarydryer._jit.long_runs`; the auto mode of
``ROTARYDRYER_JIT``). The command-line tests run one-off commands in their own processes, which
take the ahead-of-time kernels when they are built and the NumPy path otherwise, as a user's
one-off command does; the tests of each kernel compare it with its NumPy reference.

The ahead-of-time kernel module (`rotarydryer._aot`) is built here, before the first test, when
it is missing (20-60 s once per installation): a test's subprocess with a timeout never waits
for it."""

import os

from rotarydryer import _aot, _jit

_jit.long_runs()
if _jit.mode() != "off" and os.environ.get("NUMBA_DISABLE_JIT", "0").strip() in ("", "0"):
    _aot.build_now()        # a user's first long run starts it in the background and goes on with the JIT
_jit.enabled()
