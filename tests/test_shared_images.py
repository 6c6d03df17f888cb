"""Camera images to controller processes through shared memory: the policy gets the same arrays."""

from __future__ import annotations

import multiprocessing

import numpy as np

from match.protocol.spaces import IMAGE_SHAPE, CameraChoice
from match.shared_images import BLANK, ImageSlot, SharedImages, frames_of, unpack


def _observation(image: object, camera: CameraChoice) -> dict:
    return {"image": image, "camera": int(camera), "fallen": 0}


def test_images_come_back_byte_for_byte_and_the_sent_observations_are_small() -> None:
    import pickle

    images = SharedImages(multiprocessing.get_context("spawn"), 3)
    rng = np.random.default_rng(0)
    seen = rng.integers(0, 256, IMAGE_SHAPE, dtype=np.uint8)
    dark = np.zeros(IMAGE_SHAPE, np.uint8)  # a camera that is on and sees black is not a blank
    sent = {"a": _observation(seen, CameraChoice.TOP),
            "b": _observation(np.zeros(IMAGE_SHAPE, np.uint8), CameraChoice.OFF),
            "c": _observation(dark, CameraChoice.BOTTOM)}
    packed = images.pack(sent)
    assert [packed[a]["image"] for a in "abc"] == [ImageSlot(0), BLANK, ImageSlot(2)]
    assert len(pickle.dumps(packed)) < 2000
    assert sent["a"]["image"] is seen  # the caller's observations are left as they were
    received = unpack(frames_of(images.buffer), pickle.loads(pickle.dumps(packed)))
    for agent in sent:
        assert received[agent]["image"].dtype == np.uint8
        assert np.array_equal(received[agent]["image"], sent[agent]["image"]), agent
        assert {k: v for k, v in received[agent].items() if k != "image"} == {
            k: v for k, v in sent[agent].items() if k != "image"}
    seen[:] = 0  # the policy holds a copy: the next step's images do not change it
    images.pack({"a": _observation(seen, CameraChoice.TOP)})
    assert received["a"]["image"].any()


def test_what_is_not_a_camera_image_is_sent_as_it_is() -> None:
    images = SharedImages(multiprocessing.get_context("spawn"), 1)
    odd = {"a": _observation(np.zeros((4, 4, 3), np.uint8), CameraChoice.TOP),
           "b": _observation(np.zeros(IMAGE_SHAPE, np.uint8), CameraChoice.TOP),  # no slot left for it
           "c": "not an observation"}
    packed = images.pack(odd)
    assert packed["a"] is odd["a"] and packed["b"] is odd["b"] and packed["c"] == "not an observation"
    assert unpack(frames_of(images.buffer), packed) == packed
