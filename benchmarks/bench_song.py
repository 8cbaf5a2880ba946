"""Song's Ottawa pilot dryer (issue 14 parts 4-5): the 73-run prediction (target < 10 s), the
two-coefficient fit of one cross-validation half, and a simulated step test.

Every prediction is ``Simulation("song2003_ottawa", overrides).transport_steady_state()`` (the
case's predictive transport law; rotarydryer.studies.song_pilot keeps no model of its own).

Run: python benchmarks/bench_song.py          (prints a Markdown table)
     pytest benchmarks/bench_song.py --benchmark-only
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


from _timing import best  # noqa: E402

from rotarydryer.studies import song_pilot as sp  # noqa: E402

BEST = sp.Coefficients(*sp.SONG_PILOT_FITS["all"])


def predict_73_cold():
    """From nothing: the runs, the case's [[tests]] rows, 73 Simulation case loads and networks
    (each solving its curtain-velocity fixed point) and their steady states."""
    return sp.PilotModel().predict(BEST)


def predict_73(model):
    """The 73 predictions at other coefficients (one evaluation inside a fit)."""
    return model.predict(sp.Coefficients(BEST.step_factor * 1.001, BEST.curtain_coefficient))


def fit_half(model):
    idx = sp.split_halves(model.runs)["odd"]
    return sp.fit_coefficients(model, idx, start=sp.SONG_PILOT_FITS["odd"])


def step_test(model):
    i = int((model.runs.src_line == 1572).nonzero()[0][0])
    return sp.step_test(model, i, BEST)


def test_predict_73_cold(benchmark):
    benchmark.pedantic(predict_73_cold, rounds=3, iterations=1)


def test_predict_73(benchmark):
    m = sp.PilotModel()
    benchmark.pedantic(predict_73, args=(m,), rounds=3, iterations=1)


def test_step_test(benchmark):
    m = sp.PilotModel()
    benchmark.pedantic(step_test, args=(m,), rounds=3, iterations=1)


if __name__ == "__main__":
    m = sp.PilotModel()
    m.predict(BEST)
    rows = [("73-run prediction from nothing (runs, case rows, 73 Simulations and steady states)",
             best(predict_73_cold)),
            ("73-run prediction at other coefficients (one fit evaluation)", best(predict_73, m)),
            ("fit of the 2 coefficients on one half (37 runs), from SONG_PILOT_FITS", best(fit_half, m, repeat=1)),
            ("simulated up/down step test (Table 4.1 run 5) + lab analysis", best(step_test, m))]
    print("| benchmark | time (s) |")
    print("|---|---|")
    for name, t in rows:
        print(f"| {name} | {t:.3f} |")
