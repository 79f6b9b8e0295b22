"""The layers of a gibench EXR as numpy arrays, through Debian's python3-openimageio.

gibench stores layer "total" as the plain channels R, G, B (what viewers show first) and every other
layer as "<layer>.<channel>" (core/image/image.h); references add "variance", probe-cache runs
"coverage", and with "probe_views" "probe_centres" and "probe_splat".
"""

import pathlib

import numpy as np

from input_error import InputError


def read_layers(file) -> dict:
    """{layer: float32 array of height x width x channels} of every layer of `file`, channels in the
    file's order. InputError naming the file when it is missing or OpenImageIO cannot read it."""
    import OpenImageIO as oiio  # imported here: only the image views need it

    file = pathlib.Path(file)
    if not file.is_file():
        raise InputError(f"{file}: missing (expected an OpenEXR image)")
    source = oiio.ImageInput.open(str(file))
    if source is None:
        raise InputError(f"{file}: cannot read image: {oiio.geterror() or 'not an image OpenImageIO reads'}")
    try:
        spec = source.spec()
        pixels = source.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
        error = source.geterror()
    finally:
        source.close()
    if pixels is None or error:
        raise InputError(f"{file}: cannot read image: {error or 'no pixels'}")
    pixels = np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
    channels = {}
    for index, name in enumerate(spec.channelnames):
        layer, _, _ = name.rpartition(".")
        channels.setdefault(layer or "total", []).append(index)
    return {layer: pixels[:, :, indices] for layer, indices in channels.items()}


def read_layer(file, layer: str) -> np.ndarray:
    """One layer of `file` (read_layers); InputError naming the file and the layers it has when it has
    no such layer."""
    layers = read_layers(file)
    if layer not in layers:
        raise InputError(f"{file}: no layer \"{layer}\" (it has {', '.join(sorted(layers))})")
    return layers[layer]
