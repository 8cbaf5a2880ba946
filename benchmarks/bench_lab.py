"""Benchmarks for the laboratory data tools (issue 8): rig signals, images, design-load fits.

Run: pytest benchmarks/bench_lab.py --benchmark-only
"""

from rotarydryer.geometry.presets import preset_drum
from rotarydryer.lab import design_load_fit as dl
from rotarydryer.lab import flight_rig as fr
from rotarydryer.lab import images as im

RIG = fr.rig_drum("alternative")
RUN2 = fr.synthetic_run(RIG, 39.6, rpm=2.0, start_angle=93.5, bulk_density=1474.0, seed=1, noise_sd=0.1,
                        noise_correlation=0.5)  # 13.7 s at 100 Hz
PILOT = preset_drum("ajayi_pilot")[0]
PX = 2 * 950 / 0.75  # Ajayi's scale, 25.33 px/cm: 1927 x 1927 px
SYN = im.render_cross_section(PILOT, 46.7, reference_angle=91.0, px_per_m=PX, flight_thickness=0.002,
                              noise_sd=10.0, seed=1, mirror=True)
ROW = dl.ajayi_table_4_11()[0]
X, Y, _ = dl.mimic_ajayi_series(ROW["design_load_kg"], ROW["design_load_ci_kg"], ROW["FUF_area_cm2"],
                                ROW["FUF_area_ci_cm2"], seed=0)


def filter_and_rate():
    """Lee's FIR (201 taps, 1.5 Hz), zero phase, and the central-difference rate of one run."""
    return fr.mass_rate(fr.lowpass(RUN2.mass, 100.0))


def unloading_start():
    return fr.detect_unloading_start(RUN2.time, RUN2.mass)


def fit_run():
    return fr.fit_repose_angle(RUN2, RIG, rpm=2.0, start_angle=93.5, bulk_density=1474.0)


def render():
    return im.render_cross_section(PILOT, 46.7, reference_angle=91.0, px_per_m=PX, flight_thickness=0.002,
                                   noise_sd=10.0, seed=1, mirror=True)


def measure():
    return im.measure(SYN.image, PILOT, SYN.calibration, reference_angle=91.0)


def break_point():
    return dl.fit_break_point(X, Y)


def test_filter_and_rate(benchmark):
    benchmark(filter_and_rate)


def test_unloading_start_hinge(benchmark):
    benchmark(unloading_start)


def test_fit_repose_angle(benchmark):
    benchmark(fit_run)


def test_render_ajayi_scale(benchmark):
    benchmark(render)


def test_measure_ajayi_scale(benchmark):
    benchmark(measure)


def test_break_point_all_intervals(benchmark):
    benchmark(break_point)


if __name__ == "__main__":  # plain script: print timings without pytest-benchmark
    import timeit

    for f, n in ((filter_and_rate, 50), (unloading_start, 5), (fit_run, 5), (render, 2), (measure, 2),
                 (break_point, 20)):
        t = min(timeit.repeat(f, number=n, repeat=3)) / n
        print(f"{f.__name__:16s} {t * 1e3:9.3f} ms")
