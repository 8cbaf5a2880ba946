"""The compiled kernels ahead of time: one extension module per installation, loaded in about a millisecond.

The compiled kernels of `rotarydryer._jit` (the residual's gas properties, transfer and shell
network, and the flight tables of each cell) cost a process 0.5-0.7 s to load from numba's
disk cache: numba's import and its first dispatch, before any kernel runs. A sweep's parent and
each new worker pay it, one-off commands cannot (they stay on NumPy). This module compiles the
same functions once, with ``numba.pycc``, into an extension module kept in the kernel cache
(``$ROTARYDRYER_KERNEL_DIR``, else ``$XDG_CACHE_HOME/rotarydryer/kernels``; ``off`` disables
it); later processes import it without numba.

* The module's name carries a digest of the kernels' sources, this file, the Python and NumPy
  versions and the machine: a module built by other code is never loaded.
* The first process that wants compiled kernels and finds none (a long run:
  `rotarydryer._jit.long_runs`) starts its build in the background, a detached process under a
  file lock, and goes on with numba's JIT as before; the file appears by an atomic rename and
  the next processes load it. The build takes 15-60 s of one core, once. `build_now` builds it
  and waits (the test session, before its first test).
* Without a C compiler or numba, or when the build fails, a marker file records the reason (a build
  in the background fails silently, `build_now` warns once) and the processes use numba's JIT
  cache, as before; delete the marker to try again.
* Each load touches the module's file; a build removes the modules (and markers) of other sources
  that no process has loaded for `STALE_DAYS`.
* Code is generated for a generic CPU of the architecture (a cache shared by the nodes of a
  cluster must run on each), with NumPy's error model (a division by zero gives inf or NaN).
* The extension's functions check nothing: each is wrapped to accept only the declared types
  (float64 arrays, C-contiguous, outputs writeable; scalars converted) and to raise TypeError
  otherwise.

Each kernel module declares what is compiled: ``AOT_KERNELS = {name: (function, argument kinds)}``
and its helpers in ``_HELPERS`` (the functions the kernels call); argument kinds, one letter per
argument: ``a`` float64 1-D input, ``o`` float64 1-D output, ``m`` float64 2-D input, ``M`` float64
2-D output, ``n`` int64 1-D input, ``f`` float, ``i`` int, ``b`` bool.
"""

from __future__ import annotations

import errno
import hashlib
import importlib.machinery
import importlib.util
import os
import platform
import subprocess
import sys
import threading
import time
import uuid
import warnings
from pathlib import Path

import numpy as np

__all__ = ["DIR_ENV", "KERNEL_MODULES", "build", "build_now", "function", "kernel_directory", "module"]

#: environment variable naming the kernel cache directory; "off" disables the ahead-of-time kernels
DIR_ENV = "ROTARYDRYER_KERNEL_DIR"
#: the modules whose ``AOT_KERNELS`` are compiled (their files are part of the digest)
KERNEL_MODULES = ("rotarydryer.properties._kernels", "rotarydryer.geometry._cell_kernel",
                  "rotarydryer.transport._step_kernel")
_SOURCES = ("_aot.py", "properties/_kernels.py", "geometry/_cell_kernel.py", "transport/_step_kernel.py")
#: the longest a build may take, and the longest a process waits for another's (s)
BUILD_TIMEOUT = 900.0
_ARRAY_KINDS = {"a": (np.float64, 1, False), "o": (np.float64, 1, True), "m": (np.float64, 2, False),
                "M": (np.float64, 2, True), "n": (np.int64, 1, False)}
_SCALAR_KINDS = {"f": float, "i": int, "b": bool}
#: every argument kind (`AOT_KERNELS`)
KINDS = frozenset(_ARRAY_KINDS) | frozenset(_SCALAR_KINDS)

#: errno values of a lock another process holds (any other error: the file system has no locks)
_BUSY = {errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES}
_STATE: dict = {}       # "module": the loaded module or None once decided; "warned": a failure reported
_LOCK = threading.Lock()


def kernel_directory():
    """The kernel cache directory, or None when disabled (``$ROTARYDRYER_KERNEL_DIR`` = off)."""
    env = os.environ.get(DIR_ENV)
    if env is not None:
        return None if env.strip().lower() in ("", "off", "0", "none") else Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "rotarydryer" / "kernels"


def _digest() -> str:
    h = hashlib.sha256(b"rotarydryer kernels\0")
    here = Path(__file__).parent
    for name in _SOURCES:
        h.update(name.encode() + b"\0" + (here / name).read_bytes())
    h.update(repr((sys.version, np.__version__, platform.machine(), sys.platform)).encode())
    return h.hexdigest()[:16]


def _paths():
    """(directory, module name, extension file, failure marker, lock file) of this installation's module."""
    where = kernel_directory()
    if where is None:
        return None
    try:
        name = f"_rotarydryer_kernels_{_digest()}"
    except OSError:     # an installation without the kernels' sources (bytecode only, a frozen app): no module
        return None
    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    return where, name, where / (name + suffix), where / (name + ".failed"), where / (name + ".lock")


def _load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _warn(message: str) -> None:
    if not _STATE.get("warned"):
        _STATE["warned"] = True
        warnings.warn(f"rotarydryer: {message}; using numba's JIT cache", RuntimeWarning, stacklevel=4)


def module(build: bool = False):
    """The ahead-of-time kernel module of this installation, or None (disabled, not built yet, or not
    buildable here). ``build``: when it is missing, start its build in the background (a detached
    process; this process goes on with numba's JIT, as before the module existed) - a long run's
    request. Decided once per process."""
    if "module" in _STATE and (_STATE["module"] is not None or not build or _STATE.get("final")):
        return _STATE["module"]
    with _LOCK:     # one thread loads or starts the build (the web app's sessions run in threads)
        if "module" in _STATE and (_STATE["module"] is not None or not build or _STATE.get("final")):
            return _STATE["module"]
        paths = _paths()
        mod = None
        if paths is not None:
            where, name, ext, failed, lock = paths
            if ext.exists():
                mod = _try_load(name, ext)
            elif build and not failed.exists():
                _start_background(where, name, lock)
        _STATE["module"] = mod
        _STATE["final"] = mod is not None or build or paths is None
        return mod


def build_now():
    """Build the module now if it is missing (waiting for a build under way) and load it; None where it
    cannot be built (the reason warned once and kept in a marker file). What the test session does
    before its first test; `module` builds in the background instead."""
    with _LOCK:
        paths = _paths()
        if paths is None:
            return None
        where, name, ext, failed, lock = paths
        mod = _try_load(name, ext) if ext.exists() else (
            None if failed.exists() else _build_locked(where, name, ext, failed, lock))
        _STATE.update(module=mod, final=True)
        return mod


def _open_lock(where: Path, lock: Path) -> int:
    """The lock file's descriptor, the cache directory made first (OSError where it cannot be)."""
    where.mkdir(parents=True, exist_ok=True)
    return os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)


def _take_lock(fd: int):
    """Try the build's lock once: "held" (taken), "busy" (another process holds it), "none" (no locks
    here: not POSIX, or a file system without them)."""
    try:
        import fcntl
    except ImportError:
        return "none"
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return "held"
    except OSError as exc:
        return "busy" if exc.errno in _BUSY else "none"


def _start_background(where: Path, name: str, lock: Path) -> None:
    """A detached ``python -m rotarydryer._aot --background`` that builds the module under the lock (nothing
    when numba is missing, the directory cannot be made, there are no locks or a build is under way)."""
    if importlib.util.find_spec("numba") is None:
        return
    try:
        fd = _open_lock(where, lock)
    except OSError:
        return      # a read-only cache: the JIT serves, as before
    try:
        if _take_lock(fd) != "held":    # a build under way, or no lock to share (`build_now` builds then)
            return
    finally:
        os.close(fd)    # releases it: the child takes it
    try:
        child = subprocess.Popen([sys.executable, "-m", "rotarydryer._aot", "--background", str(where), name],
                                 stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                 env=_child_env(), start_new_session=True)
    except OSError:
        return
    threading.Thread(target=child.wait, daemon=True).start()    # reaped when it ends (a long-lived app)


def _child_env() -> dict:
    """The environment of a build's process: this process's package first on the path (the child compiles
    these sources and checks their digest), the JIT off."""
    root = str(Path(__file__).resolve().parent.parent)
    path = os.pathsep.join([root, *([os.environ["PYTHONPATH"]] if os.environ.get("PYTHONPATH") else [])])
    # numba's own settings (optimisation level, bounds checks, disabling) and warnings made errors are not the
    # build's: the module is shared by every later process, compiled with numba's defaults
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_") and k != "PYTHONWARNINGS"}
    return {**env, "ROTARYDRYER_JIT": "0", "PYTHONPATH": path}


def _trusted(ext: Path) -> bool:
    """Is ``ext`` this user's (or root's) and writable by no one else? Native code from a file others can
    write is not loaded."""
    if not hasattr(os, "getuid"):
        return True
    try:
        st = ext.stat()
    except OSError:
        return False
    return st.st_uid in (os.getuid(), 0) and not st.st_mode & 0o022


def _try_load(name, ext):
    if not _trusted(ext):
        _warn(f"the compiled kernel module {ext} is not loaded: another user owns it or others can write it")
        return None
    try:
        mod = _load(name, ext)
    except Exception as exc:    # noqa: BLE001 - a damaged file: the JIT instead
        _warn(f"the compiled kernel module {ext} cannot be loaded ({type(exc).__name__}: {exc})")
        return None
    try:
        os.utime(ext)           # in use: kept by `_prune` (its time is when a process last loaded it)
    except OSError:
        pass
    return mod


#: modules of other sources (older versions) not loaded for this long are removed when a new one is built
STALE_DAYS = 30.0


def _prune(where: Path, keep: str) -> None:
    cutoff = time.time() - STALE_DAYS * 86400.0
    for p in where.glob("_rotarydryer_kernels_*"):
        if p.name.startswith(keep):
            continue
        try:
            st = p.stat()
            if st.st_mtime < cutoff and (not hasattr(os, "getuid") or st.st_uid == os.getuid()):
                p.unlink()
        except OSError:
            pass


def _build_locked(where: Path, name: str, ext: Path, failed: Path, lock: Path, wait: bool = True):
    """Build under the lock (``wait``: for a build under way, else give up at once) and load."""
    if importlib.util.find_spec("numba") is None:
        return None
    try:
        fd = _open_lock(where, lock)
    except OSError as exc:
        _warn(f"the kernel cache {where} is not writable ({exc.strerror or exc})")
        return None
    try:
        deadline = time.monotonic() + BUILD_TIMEOUT
        while _take_lock(fd) == "busy":     # without locks: build without one (the rename keeps the file whole)
            if not wait or time.monotonic() > deadline:
                return None
            time.sleep(0.2)
        if ext.exists():        # built by the process that held the lock
            return _try_load(name, ext)
        if failed.exists():
            return None
        if wait and sys.stderr is not None and sys.stderr.isatty():     # a person waits: say why, once
            print("rotarydryer: compiling the kernels for this installation (once, 20-60 s) ...", file=sys.stderr,
                  flush=True)
        reason = build(where, name)
        if reason is not None:
            if not isinstance(reason, TransientBuildFailure):
                try:
                    failed.write_text(reason + "\n")
                except OSError:
                    pass
            _warn(f"the compiled kernels could not be built ahead of time ({reason})")
            return None
        _prune(where, name)
        return _try_load(name, ext)
    finally:
        os.close(fd)    # releases the lock


class TransientBuildFailure(str):
    """The reason of a build that failed for a passing cause (a signal, the time limit, the file system):
    no marker is written, a later long run tries again."""


def build(where: Path, name: str):
    """Compile the kernels into ``where/name<suffix>`` in a child process; None on success, else the
    reason (one line; a `TransientBuildFailure` for a passing cause)."""
    tmp = where / f".build-{name}-{os.getpid()}-{uuid.uuid4().hex[:8]}"
    try:
        proc = subprocess.run([sys.executable, "-m", "rotarydryer._aot", str(tmp), name], capture_output=True,
                              text=True, timeout=BUILD_TIMEOUT, env=_child_env())
        if proc.returncode < 0:     # killed (out of memory, a signal)
            return TransientBuildFailure(f"the build was stopped by signal {-proc.returncode}")
        if proc.returncode != 0:
            lines = [x for x in (proc.stderr or proc.stdout or "").splitlines() if x.strip()]
            return lines[-1].strip() if lines else f"exit code {proc.returncode}"
        built = [p for p in tmp.iterdir() if p.name.startswith(name) and p.suffix in (".so", ".pyd")]
        if not built:
            return "the compiler wrote no module"
        os.replace(built[0], where / (name + importlib.machinery.EXTENSION_SUFFIXES[0]))
        return None
    except subprocess.TimeoutExpired:
        return TransientBuildFailure(f"the build took more than {BUILD_TIMEOUT:.0f} s")
    except OSError as exc:
        return TransientBuildFailure(f"{type(exc).__name__}: {exc}")
    finally:
        if tmp.exists():
            for p in sorted(tmp.rglob("*"), reverse=True):
                try:
                    p.rmdir() if p.is_dir() else p.unlink()
                except OSError:
                    pass
            try:
                tmp.rmdir()
            except OSError:
                pass


def _guarded(fn, name: str, kinds: str):
    """``fn`` accepting only arguments of ``kinds`` (TypeError otherwise); scalars converted. The checks are
    written out per kernel (generated source, one line per argument): a loop over the kinds cost 5.6 us a call of
    ten arguments (1.8 us written out), more than some kernels' own work on a small dryer."""
    n = len(kinds)

    def bad_count(got):
        raise TypeError(f"kernel {name}: {got} arguments, expected {n}")

    def bad_array(i):
        dtype, ndim, writeable = _ARRAY_KINDS[kinds[i]]
        raise TypeError(f"kernel {name}: argument {i} must be a C-contiguous {np.dtype(dtype).name} array "
                        f"of {ndim} dimension(s){' (writeable)' if writeable else ''}")

    def bad_scalar(i):
        raise TypeError(f"kernel {name}: argument {i} must be a {_SCALAR_KINDS[kinds[i]].__name__}") from None

    names = [f"a{i}" for i in range(n)]
    env = {"_fn": fn, "_nd": np.ndarray, "_bad_count": bad_count, "_bad_array": bad_array, "_bad_scalar": bad_scalar}
    body = [f"    if len(args) != {n}:", "        _bad_count(len(args))", f"    {', '.join(names)}, = args"] if n else \
        ["    if args:", "        _bad_count(len(args))"]
    for i, k in enumerate(kinds):
        if k in _ARRAY_KINDS:
            dtype, ndim, writeable = _ARRAY_KINDS[k]
            env[f"_D{i}"] = np.dtype(dtype)
            flags = f"a{i}.flags.c_contiguous" if not writeable else f"(a{i}.flags.c_contiguous and a{i}.flags.writeable)"
            body += [f"    if type(a{i}) is not _nd or a{i}.ndim != {ndim} or (a{i}.dtype is not _D{i} and "
                     f"a{i}.dtype != _D{i}) or not {flags}:", f"        _bad_array({i})"]
        else:
            env[f"_S{i}"] = _SCALAR_KINDS[k]
            body += ["    try:", f"        a{i} = _S{i}(a{i})", "    except (TypeError, ValueError):",
                     f"        _bad_scalar({i})"]
    body.append(f"    return _fn({', '.join(names)})")
    exec(compile("def call(*args):\n" + "\n".join(body) + "\n", f"<kernel {name}>", "exec"), env)
    call = env["call"]
    call.__name__ = name
    call.aot = True
    return call


def function(name: str, kinds: str):
    """Kernel ``name`` (argument ``kinds``) from the ahead-of-time module, type-checked, or None."""
    mod = module()
    fn = getattr(mod, name, None) if mod is not None else None
    return None if fn is None else _guarded(fn, name, kinds)


def _compile(out_dir: str, name: str) -> None:
    """The child process's build: numba.pycc over every kernel module's ``AOT_KERNELS``."""
    import importlib

    if not name.endswith(_digest()):
        raise SystemExit(f"the sources found ({Path(__file__).resolve().parent}) are not those of the module "
                         f"{name} asked for")
    import numba
    import numba.pycc.compiler as pycc_compiler
    from numba.core import types
    from numba.pycc import CC

    base_flags = pycc_compiler.Flags

    class _NumpyErrors(base_flags):     # the JIT's error model: a division by zero gives inf or NaN
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            self.error_model = "numpy"

    pycc_compiler.Flags = _NumpyErrors
    cc = CC(name)
    cc.output_dir = out_dir
    cc.verbose = False
    scalars = {"f": types.float64, "i": types.int64, "b": types.boolean}
    for modname in KERNEL_MODULES:
        mod = importlib.import_module(modname)
        for helper, py in mod._HELPERS.items():     # the kernels' globals: compiled functions
            setattr(mod, helper, numba.njit(error_model="numpy")(py))
        for export, (fn, kinds) in mod.AOT_KERNELS.items():
            # the inputs read-only: a kernel that writes to an argument its kinds call an input does not compile
            args = [types.Array(types.int64 if k == "n" else types.float64, 2 if k in "mM" else 1, "C",
                                readonly=k in "amn") if k in _ARRAY_KINDS else scalars[k] for k in kinds]
            jit = numba.njit(error_model="numpy")(fn)
            jit.compile(tuple(args))
            ret = jit.overloads[tuple(args)].signature.return_type
            cc.export(export, ret(*args))(fn)
    os.makedirs(out_dir, exist_ok=True)
    cc.compile()


if __name__ == "__main__":      # python -m rotarydryer._aot OUT_DIR NAME, or --background KERNEL_DIR NAME
    if sys.argv[1] == "--background":
        found = _paths()
        if found is not None and found[1] == sys.argv[3] and not found[2].exists() and not found[3].exists():
            _build_locked(*found, wait=False)
    else:
        _compile(sys.argv[1], sys.argv[2])
