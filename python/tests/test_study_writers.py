"""converge(out_dir=…) writes the files `flexure converge -o` writes (the same library writers):
the C1/C2 study and the spectrum study, all files or none, a file refused as the folder."""

import json
import os
import struct
import zlib

import pytest

import flexure
from test_study import assert_same

# Small: one family, a ν = 1 model and midedge's ξ, two levels, two amplitudes, the refinement.
STUDY = dict(families=["patch48"], energies=["hinge", "midedge"], n=4, levels=2, amplitudes=2)
STUDY_FLAGS = ["--families", "patch48", "--energies", "hinge,midedge", "--n", "4", "--levels",
               "2", "--amplitudes", "2"]
SPECTRUM = dict(measure="modes", families=["patch48", "delaunay"], energies=["hinge", "midedge"],
                n=6, levels=2, seeds=[2], count=4, support="clamped")
SPECTRUM_FLAGS = ["--measure", "modes", "--families", "patch48,delaunay", "--energies",
                  "hinge,midedge", "--n", "6", "--levels", "2", "--seeds", "2", "--count", "4",
                  "--support", "clamped"]


def text(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def png_size(path):
    """(width, height) of a valid 8-bit RGB/RGBA PNG: signature, every chunk's CRC, IHDR first,
    IEND last, and image data that inflates to height rows of 1 + width × channels bytes."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    pos, kinds, idat = 8, [], b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        assert zlib.crc32(kind + body) == crc, f"{path}: bad CRC in {kind}"
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
        idat += body if kind == b"IDAT" else b""
        kinds.append(kind)
        pos += 12 + length
    assert kinds[0] == b"IHDR" and kinds[-1] == b"IEND" and depth == 8 and colour in (2, 6)
    assert len(zlib.decompress(idat)) == height * (1 + width * (3 if colour == 2 else 4))
    return width, height


def assert_same_folders(python_dir, cli_dir, json_name, text_names):
    """The same file names; JSON equal (floats to 1e-12), text files identical, PNGs equal."""
    names = sorted(os.listdir(cli_dir))
    assert sorted(os.listdir(python_dir)) == names
    plots = [name for name in names if name.endswith(".png")]
    assert plots and set(names) == set(plots) | {json_name, *text_names}
    with open(python_dir / json_name) as p, open(cli_dir / json_name) as c:
        assert_same(json.load(p), json.load(c), json_name)
    for name in text_names:  # no timing field in them: identical
        assert text(python_dir / name) == text(cli_dir / name), name
    for name in plots:  # valid, of the same size, and (the same writer) the same bytes
        width, height = png_size(python_dir / name)
        assert (width, height) == png_size(cli_dir / name) and width > 200 and height > 150
        with open(python_dir / name, "rb") as p, open(cli_dir / name, "rb") as c:
            assert p.read() == c.read(), name


@pytest.fixture(scope="module")
def cli_study(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("cli_study")
    cli("-q", "converge", *STUDY_FLAGS, "-o", out)
    return out


def test_study_out_dir_writes_the_cli_files(cli_study, tmp_path):
    out = tmp_path / "made" / "study"  # missing parents are created
    result = flexure.converge(**STUDY, tables=True, out_dir=out)
    assert_same_folders(out, cli_study, "results.json", ["results.csv", "summary.md"])
    assert {"c2_patch48.png", "refinement_patch48.png", "refinement_energy_patch48.png",
            "nonlinear_c2_patch48.png"} <= set(os.listdir(out))
    # tables=True: the same text as the files, beside results.json's lists.
    assert result["results.csv"] == text(out / "results.csv")
    assert result["summary.md"] == text(out / "summary.md")
    with open(cli_study / "results.json") as f:
        expected = json.load(f)
    for key in ("records", "refinement", "summary"):
        assert_same(result[key], expected[key], key)


def test_study_folder_keeps_one_studys_files(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    flexure.converge(**STUDY, out_dir=tmp_path)
    assert "nonlinear_c2_patch48.png" in os.listdir(tmp_path)
    records = flexure.converge(**dict(STUDY, amplitudes=0), out_dir=str(tmp_path))
    names = set(os.listdir(tmp_path))
    assert "nonlinear_c2_patch48.png" not in names  # the earlier study's, not this one's
    assert {"notes.txt", "results.json", "c2_patch48.png"} <= names
    with open(tmp_path / "results.json") as f:
        assert_same(records, json.load(f)["records"], "records")


def test_spectrum_records_equal_spectrum_json(cli, tmp_path):
    cli_dir, python_dir = tmp_path / "cli", tmp_path / "python"
    cli("-q", "converge", *SPECTRUM_FLAGS, "-o", cli_dir)
    series = flexure.converge(**SPECTRUM, out_dir=python_dir)
    with open(cli_dir / "spectrum.json") as f:
        expected = json.load(f)
    assert [(s["energy"], s["family"], s["seed"]) for s in series] == [
        ("hinge", "patch48", None), ("hinge", "delaunay", 2), ("midedge", "patch48", None),
        ("midedge", "delaunay", 2)]
    assert_same(series, expected["series"], "series")
    for s in series:
        assert s["n"] == [6, 12] and len(s["lambda"]) == 2 and len(s["lambda"][0]) == 4
        assert s["clamp"] in ("rings", "normals")
    assert_same_folders(python_dir, cli_dir, "spectrum.json", ["spectrum.csv", "spectrum.md"])
    whole = flexure.converge(**SPECTRUM, tables=True)
    assert_same({k: whole[k] for k in expected}, expected, "spectrum.json")
    assert whole["spectrum.md"] == text(cli_dir / "spectrum.md")
    assert whole["spectrum.csv"] == text(cli_dir / "spectrum.csv")


def test_spectrum_defaults_are_the_clis(cli, tmp_path):
    cli("-q", "converge", "--measure", "modes", "--n", "4", "--levels", "1", "--count", "2",
        "-o", tmp_path)
    summary = flexure.converge(measure="modes", n=4, levels=1, count=2, summary=True)
    with open(tmp_path / "spectrum.json") as f:
        assert_same(summary, json.load(f), "spectrum.json")
    assert summary["support"] == "simply-supported"
    assert [s["energy"] for s in summary["series"]][::2] == [
        "midedge", "cotan(voronoi)", "quadfit", "triavg", "hinge"]


def test_out_dir_that_is_a_file_is_refused_before_any_work(tmp_path):
    a_file = tmp_path / "results"
    a_file.write_text("not a folder")
    with pytest.raises(ValueError, match="out_dir .*is a file"):
        flexure.converge(**STUDY, out_dir=a_file)
    with pytest.raises(ValueError, match="out_dir .*is a file"):
        flexure.converge(**SPECTRUM, out_dir=a_file / "inside")
    assert a_file.read_text() == "not a folder"


def test_failed_study_leaves_no_folder(tmp_path):
    out = tmp_path / "never"
    with pytest.raises(ValueError, match="energies"):
        flexure.converge(**dict(STUDY, energies=["bogus"]), out_dir=out)
    with pytest.raises(ValueError, match="count"):
        flexure.converge(**dict(SPECTRUM, count=7), out_dir=out)  # Leissa tabulates six
    assert not out.exists()


@pytest.mark.parametrize("arguments, words", [
    (dict(measure="modes", amplitudes=2), "amplitudes"),
    (dict(measure="modes", quadratics=[(1, 0, 0)]), "quadratics"),
    (dict(measure="modes", solution=None), "solution"),
    (dict(support="clamped"), "support"),
    (dict(count=3), "count"),
    (dict(measure="modes", support="free"), "support"),
    (dict(measure="modes", count=0), "count"),
    (dict(measure="modes", energies=["midedge:free"]), "midedge"),
    (dict(measure="modes", families=["hexagons"]), "families"),
    (dict(out_dir=""), "out_dir"),
    (dict(out_dir=3.5), "out_dir"),
])
def test_bad_arguments_raise_value_error_naming_them(arguments, words):
    options = dict(families="patch48", energies="hinge", n=4, levels=1)
    options.update(arguments)
    with pytest.raises(ValueError, match=words):
        flexure.converge(**options)
