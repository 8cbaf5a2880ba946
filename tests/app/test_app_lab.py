"""Web app page "Lab data": its logic against the library and the CLI (same numbers, same
messages; uploads parsed in memory), and the page through Streamlit's headless AppTest harness."""

import io
import json
import re

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("streamlit")


from rotarydryer.app import logic_lab  # noqa: E402

from .apptest_support import open_app  # noqa: E402

runner = CliRunner()


def _cli(cli, args):
    res = runner.invoke(cli, args)
    return res.exit_code, res.output


def _cli_error(cli, args):
    code, out = _cli(cli, args)
    assert code == 2, out
    m = re.search(r"error: (.*)", out, re.S)
    assert m, out
    return " ".join(m.group(1).split())


def _same(msg):
    return " ".join(str(msg).split())


# ------------------------------------------------------------------------------------------- rig
RIG = ["--rpm", "2", "--start-angle", "93.5", "--bulk-density", "1474", "--repose-sd", "1.7"]


def test_rig_logic_equals_cli(cli, tmp_path):
    p = tmp_path / "run.csv"
    p.write_text(logic_lab.rig_example())
    r = logic_lab.rig_view(rpm=2.0, start_angle=93.5, bulk_density=1474.0, repose_sd=1.7, images=False)
    res = runner.invoke(cli, ["lab", "rig", str(p), "--json"] + RIG)
    assert res.exit_code == 0, res.output
    c = json.loads(res.stdout)        # stderr: the warning of the JSON's deprecated keys
    assert r["repose_angle_deg"] == pytest.approx(c["repose_angle_deg"], abs=0, rel=1e-12)
    assert r["unloading_start_s"] == c["unloading_start_s"]
    assert r["fraction_inside_band_mass"] == c["fraction_inside_band_mass"]
    assert r["repose_angle_deg"] == pytest.approx(logic_lab.RIG_EXAMPLE["repose_angle"], abs=0.2)


def test_rig_logic_bad_values_give_the_cli_messages(cli, tmp_path):
    p = tmp_path / "run.csv"
    p.write_text(logic_lab.rig_example())
    with pytest.raises(ValueError) as exc:
        logic_lab.rig_view(rpm=2.0, start_angle=300.0, bulk_density=1474.0, images=False)
    assert _same(exc.value) == _cli_error(cli, ["lab", "rig", str(p), "--rpm", "2", "--start-angle", "300",
                                                "--bulk-density", "1474"])
    with pytest.raises(ValueError) as exc:
        logic_lab.rig_view(rpm=0.0, images=False)
    assert _same(exc.value) == _cli_error(cli, ["lab", "rig", str(p), "--rpm", "0", "--start-angle", "93.5",
                                                "--bulk-density", "1474"])
    # an upload is parsed in memory; its errors name it, the line and the column
    bad = "time_s,mass_kg\n" + "".join(f"{k / 100},{k}\n" for k in range(10)) + "0.1,abc\n"
    with pytest.raises(ValueError, match=r"my.csv line 12: 'abc' is not a number in column mass_kg"):
        logic_lab.rig_view(bad, "my.csv", images=False)


def test_uploads_are_size_limited():
    big = "time_s,mass_kg\n" + "0,0\n" * (logic_lab.MAX_LAB_ROWS + 1)
    with pytest.raises(ValueError, match="data rows; the limit is"):
        logic_lab.rig_view(big, "big.csv", images=False)
    with pytest.raises(ValueError, match="bytes; the limit is"):
        logic_lab.decode_upload(b"x" * (logic_lab.MAX_LAB_UPLOAD_BYTES + 1), "big.csv")
    with pytest.raises(ValueError, match="not UTF-8"):
        logic_lab.decode_upload(b"time_s\xff", "bin.csv")


# ------------------------------------------------------------------------------------------- photographs
def _example_kwargs():
    _, e = logic_lab.image_example()
    return dict(centre=e["centre"], px_per_m=e["px_per_m"], mirror=e["mirror"], reference_angle=e["reference_angle"])


def test_image_logic_equals_library_and_the_truth():
    pytest.importorskip("skimage")
    from rotarydryer.geometry.presets import preset_drum
    from rotarydryer.lab import images as im

    content, e = logic_lab.image_example()
    r = logic_lab.image_view(images=False, **_example_kwargs())
    img = im.load_image_bytes(content)
    drum, _ = preset_drum("ajayi_pilot")
    m = im.measure(img, drum, im.ImageCalibration(e["centre"], e["px_per_m"], mirror=True),
                   reference_angle=e["reference_angle"])
    assert r["FUF_cm2"] == m.as_dict()["FUF_cm2"] and r["TP_cm2"] == m.as_dict()["TP_cm2"]
    assert r["FUF_cm2"] == pytest.approx(e["true_fuf_cm2"], rel=0.02)
    assert r["TP_cm2"] == pytest.approx(e["true_tp_cm2"], rel=0.01)


def test_image_logic_bad_values_and_pixel_ceiling(cli, tmp_path):
    pytest.importorskip("skimage")
    from PIL import Image

    content, _ = logic_lab.image_example()
    p = tmp_path / "photo.png"
    p.write_bytes(content)
    with pytest.raises(ValueError) as exc:
        logic_lab.image_view(**dict(_example_kwargs(), threshold="300"), images=False)
    assert _same(exc.value) == _cli_error(cli, ["lab", "image", str(p), "--centre", "313,313", "--px-per-m", "800",
                                                "--threshold", "300"])
    with pytest.raises(ValueError) as exc:
        logic_lab.image_view(**dict(_example_kwargs(), centre=(5000.0, 313.0)), name=str(p), images=False)
    assert _same(exc.value) == _cli_error(cli, ["lab", "image", str(p), "--centre", "5000,313", "--px-per-m", "800"])
    # the pixel count is checked from the header, before decoding
    buf = io.BytesIO()
    Image.new("L", (2100, 2000)).save(buf, format="PNG")
    with pytest.raises(ValueError, match="4.2 megapixels\\); the limit is 4 megapixels"):
        logic_lab.image_view(buf.getvalue(), "huge.png", **_example_kwargs(), images=False)
    with pytest.raises(ValueError, match="not a readable image file"):
        logic_lab.image_view(b"not an image", "x.png", **_example_kwargs(), images=False)


# ------------------------------------------------------------------------------------------- design load
def test_design_load_logic_equals_cli(cli, tmp_path):
    p = tmp_path / "series.csv"
    p.write_text(logic_lab.design_load_example())
    r = logic_lab.design_load_view(images=False)
    code, out = _cli(cli, ["lab", "design-load", str(p), "--group-column", "condition", "--json"])
    assert code == 0, out
    c = json.loads(out)["fits"]
    assert [f["group"] for f in r["fits"]] == list(c)
    for f in r["fits"]:
        assert f["design_load"] == c[f["group"]]["design_load"]
        assert list(f["profile_ci"]) == c[f["group"]]["ci"]["profile"]
    assert len(r["fits"]) == 9          # one per row of Ajayi's Table 4.11


def test_design_load_logic_bad_column_gives_the_cli_message(cli, tmp_path):
    p = tmp_path / "series.csv"
    p.write_text(logic_lab.design_load_example())
    with pytest.raises(ValueError) as exc:
        logic_lab.design_load_view(None, str(p), area_column="FUF", images=False)
    assert _same(exc.value) == _cli_error(cli, ["lab", "design-load", str(p), "--area-column", "FUF",
                                                "--group-column", "condition"])


# ------------------------------------------------------------------------------------------- steps
def test_steps_logic_equals_cli(cli, tmp_path):
    p = tmp_path / "steps.csv"
    p.write_text(logic_lab.steps_example())
    r = logic_lab.steps_view(images=False)
    code, out = _cli(cli, ["lab", "steps", str(p), "--json"])
    assert code == 0, out
    c = json.loads(out)
    assert r["h_up_kg"] == c["h_up_kg"] and r["h_down_kg"] == c["h_down_kg"]
    assert r["segments"] == c["segments"]
    assert r["h_up_kg"] == pytest.approx(31.27, abs=0.05)     # Song's run 2 simulated; Table 4.1: 29.93 kg


def test_steps_logic_bad_values_give_the_cli_messages(cli, tmp_path):
    p = tmp_path / "steps.csv"
    p.write_text(logic_lab.steps_example())
    with pytest.raises(ValueError) as exc:
        logic_lab.steps_view(None, str(p), step_times="5,2", images=False)
    assert _same(exc.value) == _cli_error(cli, ["lab", "steps", str(p), "--steps", "5,2"])
    with pytest.raises(ValueError) as exc:
        logic_lab.steps_view(threshold=1.5, images=False)
    assert _same(exc.value) == _cli_error(cli, ["lab", "steps", str(p), "--threshold", "1.5"])


# ------------------------------------------------------------------------------------------- page
def test_lab_page_renders_every_tab_and_updates():
    at = open_app("Lab data", timeout=240)
    labels = [m.label for m in at.metric]
    for label in ("Repose angle (deg)", "FUF (cm2)", "Design load, 1st group", "Holdup H1 (kg)"):
        assert label in labels
    values = {m.label: m.value for m in at.metric}
    at.number_input(key="lab_rig_sd").set_value(0.5).run()
    at.number_input(key="lab_steps_h0").set_value(1.0).run()
    at.number_input(key="lab_dl_conf").set_value(0.8).run()
    assert not at.exception
    new = {m.label: m.value for m in at.metric}
    assert new["Mass in band (%)"] != values["Mass in band (%)"]
    assert new["Closure (%)"] != values["Closure (%)"]
    # a bad value in one tab: the CLI's message there, the other tabs still shown
    at.number_input(key="lab_rig_start").set_value(300.0).run()
    assert not at.exception
    assert any("--start-angle = 300 deg is past the end of unloading" in e.value for e in at.error)
    assert "Holdup H1 (kg)" in [m.label for m in at.metric]
    assert np.isfinite(float(new["Design load, 1st group"]))
