"""Integrity of the on-disk geometry table cache (``rotarydryer.geometry.tabulated``).

Every entry file carries the record of what it was built from and a sha256 of its arrays; a
file that is changed, damaged or not ours is ignored with one :class:`GeometryCacheWarning`
and rebuilt (replaced atomically). Each test uses a private cache directory.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import warnings

import numpy as np
import pytest

import rotarydryer.geometry.tabulated as T
from rotarydryer.geometry import FlightedDrum, PolygonFlight, TwoSectionFlight
from rotarydryer.geometry.tabulated import GeometryCacheWarning

PHI = np.linspace(12.0, 78.0, 401)
F = np.linspace(0.0, 1.0, PHI.size) ** 1.5
_TABLE = T.GeometryTable


@pytest.fixture()
def cache(monkeypatch, tmp_path):
    """A private on-disk cache directory, an empty in-memory cache, no bad files reported yet,
    and a count of the tables built from the exact geometry (not loaded)."""
    d = tmp_path / "cache"
    monkeypatch.setenv(T.CACHE_ENV, str(d))
    monkeypatch.setattr(T, "_cache", type(T._cache)())
    monkeypatch.setattr(T, "_warned", set())
    built = []

    class Counting(T.GeometryTable):
        def __init__(self, *args, **kwargs):
            built.append(kwargs.get("_fitted") is None)
            super().__init__(*args, **kwargs)

    monkeypatch.setattr(T, "GeometryTable", Counting)

    class Cache:
        dir = d

        @staticmethod
        def builds():
            return sum(built)

        @staticmethod
        def forget():
            """A new process: the in-memory cache emptied (the files stay)."""
            T._cache.clear()

    return Cache


def _values(table):
    """What the dryer models take from a table, on fixed points, as one array."""
    cs = table.cascade(PHI, F, rpm=3.0, slope=2.0)
    d = np.linspace(0.0, 1.3, PHI.size)
    return np.concatenate([cs.mean_release_angle, cs.mean_fall_height, cs.mean_fall_time, cs.passive_time,
                           table.design_load_area(PHI), table.design_load_area(PHI, method="ajayi2011"),
                           table.loading_factor(d, PHI)])


@pytest.fixture(scope="module")
def clean_entries(tmp_path_factory):
    """A clean run's entry files and values per drum, built once for the module."""
    built = {}

    def get(drum):
        key = T._key(drum)
        if key not in built:
            with pytest.MonkeyPatch.context() as mp:
                d = tmp_path_factory.mktemp("clean")
                mp.setenv(T.CACHE_ENV, str(d))
                mp.setattr(T, "_cache", type(T._cache)())
                mp.setattr(T, "GeometryTable", _TABLE)    # not counted as a build of the test
                table = T.geometry_table(drum)
                (path,) = d.glob("*.npz")
                built[key] = (path.name, path.read_bytes(), _values(table))
        return built[key]

    return get


def _entry(cache, drum, clean_entries):
    """The entry file of ``drum`` in the test's cache directory as a clean run left it, and the
    clean run's values."""
    name, data, values = clean_entries(drum)
    cache.dir.mkdir(exist_ok=True)
    path = cache.dir / name
    path.write_bytes(data)
    return path, values


def _arrays(path):
    with np.load(path, allow_pickle=False) as f:
        return {k: f[k] for k in f.files}


def _rehash(a):
    """The entry ``a`` with its sha256 recomputed (a change the content hash cannot see)."""
    a["sha256"] = np.array(T._content_digest(str(a["meta"][()]), a))
    return a


def _rebuilt(cache, drum, path, match, clean):
    """Load ``drum``'s table over the bad file ``path``: one warning naming the file and
    ``match``, the table rebuilt with the clean values, the file replaced by a valid entry."""
    n = cache.builds()
    with pytest.warns(GeometryCacheWarning, match=match) as rec:
        table = T.geometry_table(drum)
    bad = [w for w in rec if issubclass(w.category, GeometryCacheWarning)]
    assert len(bad) == 1 and path.name in str(bad[0].message)
    assert cache.builds() == n + 1
    np.testing.assert_allclose(_values(table), clean, rtol=1e-12, atol=0.0)
    # the replacement is a valid entry: loaded without a warning and without a build
    cache.forget()
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryCacheWarning)
        again = T.geometry_table(drum)
    assert cache.builds() == n + 1
    np.testing.assert_array_equal(_values(again), _values(table))
    assert T._load_disk(path, T._key(drum), drum, "root", "chord")[1] is None


def test_valid_file_is_loaded_not_rebuilt(cache, invicta, clean_entries):
    path, clean = _entry(cache, invicta, clean_entries)     # as a clean run (another process) left it
    before = path.read_bytes(), path.stat().st_ino, path.stat().st_mtime_ns
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryCacheWarning)
        table = T.geometry_table(invicta)
    assert cache.builds() == 0
    assert (path.read_bytes(), path.stat().st_ino) == before[:2]     # not rewritten
    assert path.stat().st_mtime_ns >= before[2]                      # marked as used (the prune's order)
    np.testing.assert_array_equal(_values(table), clean)
    a = _arrays(path)
    assert set(a) == set(T._FILE_ARRAYS)
    assert str(a["meta"][()]) == T._entry_meta(T._key(invicta))
    assert str(a["sha256"][()]) == T._content_digest(str(a["meta"][()]), a)


def test_tampered_values_times_3_are_rebuilt(cache, invicta, clean_entries):
    path, clean = _entry(cache, invicta, clean_entries)
    a = _arrays(path)
    a["blocks"] = a["blocks"] * 3.0      # a valid .npz, its stored sha256 left as it was
    np.savez(path, **a)
    _rebuilt(cache, invicta, path, "sha256", clean)


@pytest.mark.parametrize("what", ["edges", "phi_range", "nx", "holdup_coef", "y_grid"])
def test_any_changed_array_is_detected(cache, invicta, clean_entries, what):
    path, clean = _entry(cache, invicta, clean_entries)
    a = _arrays(path)
    if what == "nx":
        a["nx"] = a["nx"][::-1].copy()
    else:
        a[what] = np.nextafter(a[what], np.inf)     # one ulp
    np.savez(path, **a)
    _rebuilt(cache, invicta, path, "sha256", clean)


def test_nan_values_are_rebuilt(cache, invicta, clean_entries):
    path, clean = _entry(cache, invicta, clean_entries)
    a = _arrays(path)
    a["blocks"][5:9, 10:20] = np.nan
    np.savez(path, **a)
    _rebuilt(cache, invicta, path, "sha256", clean)
    # the same with a matching sha256: the finite check on its own
    cache.forget()
    a = _arrays(path)
    a["holdup_coef"][1, 3, 0] = np.inf
    np.savez(path, **_rehash(a))
    _rebuilt(cache, invicta, path, "non-finite", clean)


def test_wrong_shapes_or_grid_with_a_matching_hash_are_rebuilt(cache, invicta, clean_entries):
    path, clean = _entry(cache, invicta, clean_entries)
    a = _arrays(path)
    a["blocks"] = a["blocks"][:, :-1].copy()
    np.savez(path, **_rehash(a))
    _rebuilt(cache, invicta, path, "wrong shapes", clean)
    cache.forget()
    a = _arrays(path)
    a["blocks"] = a["blocks"].astype(np.float32)
    np.savez(path, **_rehash(a))
    _rebuilt(cache, invicta, path, "float32|<f4", clean)
    cache.forget()
    a = _arrays(path)
    a["edges"] = a["edges"] + 0.25         # finite, right shapes, not the drum's grid
    np.savez(path, **_rehash(a))
    _rebuilt(cache, invicta, path, "grid does not fit", clean)
    cache.forget()
    a = _arrays(path)
    a["phi_range"] = np.array([10.0, 79.0])
    np.savez(path, **_rehash(a))
    _rebuilt(cache, invicta, path, "repose-angle range", clean)


@pytest.mark.parametrize("damage", ["truncated", "garbage", "empty", "npy", "zip_no_npz"])
def test_truncated_or_garbage_file_is_rebuilt(cache, invicta, clean_entries, damage, tmp_path):
    path, clean = _entry(cache, invicta, clean_entries)
    data = path.read_bytes()
    if damage == "truncated":
        path.write_bytes(data[: len(data) // 2])
        match = "truncated"
    elif damage == "garbage":
        path.write_bytes(b"not a table" * 100)
        match = "not an .npz"
    elif damage == "empty":
        path.write_bytes(b"")
        match = "not an .npz"
    elif damage == "npy":
        np.save(tmp_path / "x.npy", np.ones(10))
        path.write_bytes((tmp_path / "x.npy").read_bytes())
        match = "not an .npz"
    else:
        path.write_bytes(b"PK\x03\x04" + os.urandom(4000))
        match = "truncated or unreadable"
    _rebuilt(cache, invicta, path, match, clean)


def test_foreign_npz_is_rebuilt(cache, invicta, clean_entries):
    path, clean = _entry(cache, invicta, clean_entries)
    np.savez(path, x=np.arange(3.0), values=np.ones((3, 2, 2)))
    _rebuilt(cache, invicta, path, "not a geometry table", clean)
    # an entry without its record and hash (the previous format)
    cache.forget()
    a = _arrays(path)
    np.savez(path, **{k: a[k] for k in T._TABLE_ARRAYS})
    _rebuilt(cache, invicta, path, "not a geometry table", clean)


def test_another_entry_under_this_name_is_not_ours(cache, invicta, clean_entries):
    other = FlightedDrum(1.95, 30, TwoSectionFlight(0.15, 0.12, 90.0, 135.0))
    path, clean = _entry(cache, invicta, clean_entries)
    T.geometry_table(other)
    (other_path,) = set(cache.dir.glob("*.npz")) - {path}
    cache.forget()
    path.write_bytes(other_path.read_bytes())    # a valid entry, with a matching hash, of another drum
    _rebuilt(cache, invicta, path, "not this entry", clean)


def test_one_warning_per_bad_file(cache, invicta, clean_entries, monkeypatch):
    path, clean = _entry(cache, invicta, clean_entries)
    path.write_bytes(b"garbage")
    monkeypatch.setattr(T, "_save_disk", lambda *a: None)     # the bad file cannot be replaced
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        for _ in range(3):
            T.geometry_table(invicta)
            cache.forget()
    bad = [w for w in rec if issubclass(w.category, GeometryCacheWarning)]
    assert len(bad) == 1
    assert str(path) in str(bad[0].message) and "not an .npz" in str(bad[0].message)
    # a new bad file (other content) is reported again
    path.write_bytes(b"other garbage")
    with pytest.warns(GeometryCacheWarning, match="not an .npz"):
        T.geometry_table(invicta)


def test_key_covers_drum_convention_code_and_format(cache, invicta, monkeypatch):
    key = T._key(invicta)
    p = T._disk_path(key)
    assert p.parent == cache.dir and p.suffix == ".npz"
    assert T._disk_path(T._key(invicta)) == p
    assert T._disk_path(T._key(invicta, convention="tip")) != p
    assert T._disk_path(T._key(invicta, fall_height="eq3.5")) != p
    assert T._disk_path(T._key(FlightedDrum(2.5, 30, invicta.flight))) != p
    n_f, fmt = T.N_F, T.CACHE_FORMAT
    try:
        T.CACHE_FORMAT = fmt + 1
        assert T._disk_path(key) != p
        T.CACHE_FORMAT = fmt
        T.N_F = 2 * n_f                # a grid parameter: part of the code digest
        T._source_digest.cache_clear()
        assert T._disk_path(key) != p
    finally:
        T.N_F, T.CACHE_FORMAT = n_f, fmt
        T._source_digest.cache_clear()
    assert T._disk_path(key) == p


def test_concurrent_writers_and_readers_see_whole_files(cache, invicta, clean_entries):
    path, clean = _entry(cache, invicta, clean_entries)
    table = T.geometry_table(invicta)
    key = T._key(invicta)
    stop = threading.Event()
    errors = []

    def writer():
        while not stop.is_set():
            T._save_disk(path, table, key)

    threads = [threading.Thread(target=writer) for _ in range(2)]
    for t in threads:
        t.start()
    try:
        for _ in range(6):
            got, reason = T._load_disk(path, key, invicta, "root", "chord")
            if reason is not None or got is None:
                errors.append(reason)
    finally:
        stop.set()
        for t in threads:
            t.join()
    assert errors == []
    assert sorted(p.name for p in cache.dir.iterdir()) == [path.name]    # no temporary file left


def test_concurrent_processes_build_one_valid_entry(cache):
    code = ("import warnings; warnings.simplefilter('error');"
            "from rotarydryer.geometry import FlightedDrum, TwoSectionFlight;"
            "from rotarydryer.geometry.tabulated import geometry_table;"
            "geometry_table(FlightedDrum(1.2, 18, TwoSectionFlight(0.1, 0.08, 90.0, 120.0)))")
    env = dict(os.environ)
    procs = [subprocess.Popen([sys.executable, "-c", code], env=env, stderr=subprocess.PIPE, text=True)
             for _ in range(2)]
    for p in procs:
        _, err = p.communicate(timeout=120)
        assert p.returncode == 0, err
    (path,) = cache.dir.glob("*.npz")
    assert sorted(p.name for p in cache.dir.iterdir()) == [path.name]
    drum = FlightedDrum(1.2, 18, TwoSectionFlight(0.1, 0.08, 90.0, 120.0))
    table, reason = T._load_disk(path, T._key(drum), drum, "root", "chord")
    assert reason is None and table is not None


def test_tampered_cache_does_not_change_a_shipped_case(cache):
    """The attacker's finding: a valid .npz with values x 3 changed a shipped case's total
    holdup with no error; now the file is rebuilt and the result is the clean run's."""
    from rotarydryer import Simulation

    clean = Simulation("song2003_ottawa").transport_steady_state().total_holdup
    files = list(cache.dir.glob("*.npz"))
    assert files
    for p in files:
        a = _arrays(p)
        a["blocks"] = a["blocks"] * 3.0
        np.savez(p, **a)
    cache.forget()
    with pytest.warns(GeometryCacheWarning, match="sha256"):
        again = Simulation("song2003_ottawa").transport_steady_state().total_holdup
    assert again == pytest.approx(clean, rel=1e-12)


def test_an_entry_is_read_directly_and_a_compressed_one_still_loads(cache, invicta, clean_entries):
    """An entry as the code writes it (numpy.savez, members stored) is read member by member at its offset in the
    file (one readinto each, no pass of the zip layer's CRC): the arrays equal numpy.load's, each aligned and its
    own (an array mapped in place from a zip member is not aligned to 8 bytes, and gathers from it were 16x slower).
    The same entry written compressed is read by numpy.load instead: loaded, not rebuilt."""
    path, clean = _entry(cache, invicta, clean_entries)
    with open(path, "rb") as fh:
        stored = T._read_stored_npz(fh)
    assert stored is not None and set(stored.files) == set(T._FILE_ARRAYS)
    ref = _arrays(path)
    for k in ref:
        np.testing.assert_array_equal(stored[k], ref[k])
        assert stored[k].dtype == ref[k].dtype and stored[k].shape == ref[k].shape
        assert stored[k].flags.aligned and stored[k].base is None or stored[k].base.flags.owndata
    n = cache.builds()
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryCacheWarning)
        table = T.geometry_table(invicta)
    assert cache.builds() == n
    np.testing.assert_allclose(_values(table), clean, rtol=1e-12, atol=0.0)

    np.savez_compressed(path, **ref)
    with open(path, "rb") as fh:
        assert T._read_stored_npz(fh) is None
    cache.forget()
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryCacheWarning)
        table = T.geometry_table(invicta)
    assert cache.builds() == n
    np.testing.assert_allclose(_values(table), clean, rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("flight", [TwoSectionFlight(s1=0.1, s2=0.08, alpha2=135.0),
                                    TwoSectionFlight(s1=0.1, s2=0.0, alpha2=135.0),
                                    PolygonFlight([(0.195, 90.0), (0.10, 135.0), (0.09, 135.0)])])
def test_key_text_of_a_flight_is_its_profile_every_time(flight):
    """The key's flight text is remembered per flight value (a study rebuilds its sections every run): the
    same text as the drum's profile, a new flight value a new text."""
    drum = FlightedDrum(1.0, 12, flight)
    want = ";".join(f"{float(a)!r},{float(b)!r}" for a, b in drum.profile.segments)
    for _ in range(2):
        assert T._key(drum)[2] == want
        assert T._key(FlightedDrum(1.0, 12, flight))[2] == want
    other = FlightedDrum(1.0, 12, TwoSectionFlight(s1=0.11, s2=0.08, alpha2=135.0))
    assert T._key(other)[2] != want


def _fake_entries(d, n, size=1000):
    """``n`` entry-named files of ``size`` bytes in ``d``, oldest first (modification times 1 s apart)."""
    d.mkdir(parents=True, exist_ok=True)
    paths = []
    for i in range(n):
        p = d / f"{i:032x}.npz"
        p.write_bytes(b"PK\x03\x04" + b"\0" * (size - 4))
        os.utime(p, ns=(10**18 + i * 10**9, 10**18 + i * 10**9))
        paths.append(p)
    return paths


def test_the_disk_cache_keeps_its_size_limit_removing_the_least_recently_used(cache, monkeypatch):
    """A sweep over drum sizes writes one 14 MB entry per drum: after a write, the oldest entries beyond
    `ROTARYDRYER_CACHE_MAX_MB` are removed, the new one and the user's other files never; a load marks its entry as
    used, so a drum met again outlives older ones."""
    old = _fake_entries(cache.dir, 5)
    (cache.dir / "notes.txt").write_text("mine")            # not an entry: never counted or removed
    (cache.dir / f"{'f' * 32}.npz").mkdir()                 # not a regular file: never removed
    drum = FlightedDrum(1.2, 18, TwoSectionFlight(0.1, 0.08, 90.0, 120.0))
    probe = T._disk_path(T._key(drum))
    monkeypatch.setenv(T.CACHE_MAX_ENV, str(3000 / 1e6))    # 3000 bytes: less than the new entry alone
    T.geometry_table(drum)
    assert probe.is_file() and cache.builds() == 1
    assert not any(p.exists() for p in old)                 # all older entries removed, the new one kept
    assert (cache.dir / "notes.txt").read_text() == "mine" and (cache.dir / f"{'f' * 32}.npz").is_dir()
    # least recently used: touch the oldest of three, then prune to two entries' worth
    a, b, c = _fake_entries(cache.dir / "lru", 3)
    os.utime(a)                                             # a load of `a` (what geometry_table does)
    removed = T.prune_disk_cache(cache.dir / "lru", limit_bytes=2000)
    assert removed == [b] and a.exists() and c.exists()


def test_a_loaded_entry_is_marked_as_used(cache):
    drum = FlightedDrum(1.2, 18, TwoSectionFlight(0.1, 0.08, 90.0, 120.0))
    T.geometry_table(drum)
    path = T._disk_path(T._key(drum))
    os.utime(path, ns=(10**18, 10**18))
    cache.forget()
    T.geometry_table(drum)
    assert cache.builds() == 1 and path.stat().st_mtime_ns > 10**18


@pytest.mark.parametrize("value", ["abc", "2GB", "0", "-5", "nan", "inf", "1e13"])
def test_a_bad_cache_limit_is_refused_naming_the_variable(cache, monkeypatch, value):
    """Refused before any work, on a disk hit as on a miss (not after a table's build); with the disk cache off the
    limit is not read."""
    monkeypatch.setenv(T.CACHE_MAX_ENV, value)
    drum = FlightedDrum(1.2, 18, TwoSectionFlight(0.1, 0.08, 90.0, 120.0))
    with pytest.raises(ValueError, match=rf"ROTARYDRYER_CACHE_MAX_MB = '{value}'.*number of MB in \(0, 1e12\)"):
        T.geometry_table(drum)
    assert cache.builds() == 0 and (not cache.dir.exists() or not list(cache.dir.glob("*.npz")))
    monkeypatch.delenv(T.CACHE_MAX_ENV)
    T.geometry_table(drum)                     # an entry on disk
    cache.forget()
    monkeypatch.setenv(T.CACHE_MAX_ENV, value)
    with pytest.raises(ValueError, match="ROTARYDRYER_CACHE_MAX_MB"):
        T.geometry_table(drum)                 # a disk hit is refused too
    monkeypatch.setenv(T.CACHE_ENV, "off")
    assert T.geometry_table(drum) is not None and T.prune_disk_cache() == []
