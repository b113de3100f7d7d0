"""The PNG writer (solver.io.png) against independent decoders (Pillow, matplotlib's reader),
and the pictures it writes against matplotlib's own ``savefig`` of the same figure."""

import numpy as np
import pytest

from ibfem.solver.io.png import write_png

Image = pytest.importorskip("PIL.Image")


def test_pixels_and_resolution_read_back_as_written(tmp_path):
    rng = np.random.default_rng(3)
    for shape in [(1, 1, 3), (7, 13, 3), (64, 33, 3)]:
        rgb = rng.integers(0, 256, shape, dtype=np.uint8)
        rgb[: shape[0] // 2] = rgb[: shape[0] // 2] // 4  # rows that differ much and little from the next
        path = tmp_path / f"p{shape[0]}.png"
        write_png(path, rgb, dpi=110)
        with Image.open(path) as im:
            assert im.mode == "RGB" and im.size == (shape[1], shape[0])
            assert np.array_equal(np.asarray(im), rgb)
            assert im.info["dpi"] == pytest.approx((110, 110), abs=0.01)


def test_a_flat_picture_compresses(tmp_path):
    rgb = np.full((500, 800, 3), 255, dtype=np.uint8)
    rgb[100:400, 100:700] = np.linspace(0, 255, 600).astype(np.uint8)[None, :, None]
    write_png(tmp_path / "flat.png", rgb)
    assert (tmp_path / "flat.png").stat().st_size < rgb.nbytes / 50


def test_a_figure_is_written_with_savefigs_pixels(tmp_path):
    pytest.importorskip("matplotlib")
    from ibfem.solver.io import plots

    figs = plots.AggFigures()
    fig, ax = figs.subplots(figsize=(5, 3))
    x = np.linspace(0.0, 1.0, 50)
    ax.plot(x, np.sin(7 * x), label="sin")
    ax.tripcolor(x[:-2:3], np.cos(x[:-2:3]), np.arange(16.0), shading="gouraud")
    ax.set_title("a figure")
    ax.legend()
    fig.savefig(tmp_path / "savefig.png", dpi=plots._DPI)
    plots._save_drawn(fig, tmp_path / "ours.png")
    with Image.open(tmp_path / "savefig.png") as a, Image.open(tmp_path / "ours.png") as b:
        assert np.array_equal(np.asarray(a.convert("RGB")), np.asarray(b))


def test_not_rgb_pixels_are_refused(tmp_path):
    with pytest.raises(ValueError, match=r"x\.png: expected \(height, width, 3\) uint8"):
        write_png(tmp_path / "x.png", np.zeros((4, 4), dtype=np.uint8))
