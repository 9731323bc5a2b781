"""Our Lottie played by the players people ship with, beside lottie-web (browser-tests): Samsung's
rlottie (PyPI ``rlottie-python``, the player of Telegram stickers) and ThorVG (PyPI
``thorvg-python``, the engine of the dotLottie players). Every frame drawn is compared with our
own rendering of the same frame of the same animation (``splineskin animate -o DIR/ --png``),
as a mean difference per channel over the picture flattened on white, with a control: the same
player's frame against a frame of ours where the art is posed otherwise, which must differ far
more. Three animations: the bundled fish (gradients), and our own scenes on two real emoji
nobody here drew, Noto's flamingo (gradients) and OpenMoji's turtle (test-art's npm packages)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from conftest import ASSETS, REPO, run_cli

try:
    import thorvg_python as tvg
    from PIL import Image
    from rlottie_python import LottieAnimation
except ImportError:
    if os.environ.get("CI"):
        raise  # .ci/run installs the players: their absence there is an error
    pytest.skip("the Lottie players are not installed (pip install rlottie-python thorvg-python pillow)",
                allow_module_level=True)

ART = REPO / "test-art" / "node_modules"
NOTO = ART / "@iconify-json" / "noto" / "icons.json"
TURTLE = ART / "openmoji" / "color" / "svg" / "1F422.svg"

#: Mean difference per channel (of 255) within which a player's frame is ours. Measured: at
#: most 2.13 (rlottie, the fish's gradients), 1.40 (ThorVG), over every frame; the fish's text label is
#: not written to Lottie, and players anti-alias differently.
SAME = 2.5
#: How much more a control frame (the art posed otherwise) must differ.
CONTROL_RATIO = 3.0


def art(name: str, tmp: Path) -> list[str]:
    """The input and the pose arguments of animation `name`, the art written into `tmp`."""
    if name == "fish":
        return [str(ASSETS / "demo-scene.json")]
    if not NOTO.exists() or not TURTLE.exists():
        if os.environ.get("CI"):
            pytest.fail(f"{ART}: the art packages are missing (npm ci in test-art)")
        pytest.skip(f"the art packages are missing: {ART} (npm ci in test-art)")
    if name == "flamingo":
        noto = json.loads(NOTO.read_text())
        svg = tmp / "flamingo.svg"
        svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="256" height="256" '
                       f'viewBox="0 0 {noto["width"]} {noto["height"]}">{noto["icons"]["flamingo"]["body"]}</svg>')
        return [str(svg), "--pins", "4", "--rotate", "2:30"]
    return [str(TURTLE), "--pins", "4", "--move", "1:8,-6"]


def flattened(image: "Image.Image", premultiplied: bool = False) -> np.ndarray:
    """RGB over white, as floats. rlottie and ThorVG give their pixels premultiplied by alpha
    (half-opaque #cc0000 comes back as (102, 0, 0, 127)): those are composited as such."""
    rgba = np.asarray(image.convert("RGBA"), dtype=float)
    rgb, alpha = rgba[..., :3], rgba[..., 3:] / 255.0
    if not premultiplied:
        rgb = rgb * alpha
    return rgb + 255.0 * (1.0 - alpha)


class ThorVG:
    """ThorVG's software canvas playing one Lottie file."""

    def __init__(self, path: Path):
        self.engine = tvg.Engine()
        self.engine.init(1)
        self.path = str(path)

    def frame(self, f: int, width: int, height: int) -> "Image.Image":
        canvas = tvg.SwCanvas(self.engine)
        canvas.set_target(width, height)
        animation = tvg.LottieAnimation(self.engine)
        picture = animation.get_picture()
        picture.load(self.path)
        picture.set_size(width, height)
        animation.set_frame(f)
        canvas.add(picture)
        canvas.update()
        canvas.draw(True)
        canvas.sync()
        return canvas.get_pillow()


@pytest.mark.parametrize("name", ["fish", "flamingo", "turtle"])
def test_rlottie_and_thorvg_play_our_lottie_as_we_draw_it(name: str, tmp_path: Path) -> None:
    source = art(name, tmp_path)
    lottie = tmp_path / f"{name}.json"
    run_cli("animate", *source, "-o", str(lottie))
    run_cli("animate", *source, "-o", f"{tmp_path / 'frames'}/", "--png")
    document = json.loads(lottie.read_text())
    # What rlottie and Skottie need: whole numbers where they read integers.
    for key in ("w", "h", "ip", "op"):
        assert isinstance(document[key], int), f"{key}: {document[key]!r}"
    ours = lambda f: Image.open(tmp_path / "frames" / f"frame-{f:04d}.png")  # noqa: E731
    n = len(list((tmp_path / "frames").glob("frame-*.png")))
    rlottie = LottieAnimation.from_file(str(lottie))
    assert rlottie.lottie_animation_get_totalframe() == n
    thorvg = ThorVG(lottie)
    # Every frame; the rest, the pose and a third of the way back also against a control, the
    # frame farthest from it in pose (the pose for the ends, the rest for the middle).
    report = []
    controlled = [0, n // 2, (5 * n) // 6]
    worst = {"rlottie": 0.0, "ThorVG": 0.0}
    for f in range(n):
        control = flattened(ours(n // 2 if f in (0, n - 1) else 0))
        image = ours(f)
        expected = flattened(image)
        played = {
            "rlottie": rlottie.render_pillow_frame(frame_num=f, width=image.size[0], height=image.size[1]),
            "ThorVG": thorvg.frame(f, *image.size),
        }
        for player, picture in played.items():
            got = flattened(picture, premultiplied=True)
            same = np.abs(got - expected).mean()
            worst[player] = max(worst[player], same)
            assert same <= SAME, f"{name}, {player}, frame {f}: {same:.2f}/255 from ours"
            if f in controlled:
                other = np.abs(got - control).mean()
                report.append(f"{player} frame {f}: {same:.2f} (control {other:.2f})")
                assert other >= CONTROL_RATIO * same, f"{name}, {player}, frame {f}: the control differs by only {other:.2f}"
    print(f"{name}: {n} frames, largest rlottie {worst['rlottie']:.2f}, ThorVG {worst['ThorVG']:.2f}; " + "; ".join(report))
