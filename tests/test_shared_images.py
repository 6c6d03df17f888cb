"""Camera images to controller processes through shared memory: the policy gets the same arrays."""

from __future__ import annotations

import multiprocessing
import os

import numpy as np

from match.protocol.spaces import IMAGE_SHAPE, CameraChoice
from match.shared_images import BLANK, ImageSlot, SharedImages, receive_frames, unpack


def _handed_over(images: SharedImages) -> np.ndarray:
    """The slots as a controller process maps them, handed over through a pipe (here to this process)."""
    ours, theirs = multiprocessing.Pipe()
    try:
        images.hand_over(ours, os.getpid())
        return receive_frames(theirs)
    finally:
        ours.close()
        theirs.close()


def _observation(image: object, camera: CameraChoice) -> dict:
    return {"image": image, "camera": int(camera), "fallen": 0}


def test_images_come_back_byte_for_byte_and_the_sent_observations_are_small() -> None:
    import pickle

    images = SharedImages(3)
    frames = _handed_over(images)
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
    received = unpack(frames, pickle.loads(pickle.dumps(packed)))
    for agent in sent:
        assert received[agent]["image"].dtype == np.uint8
        assert np.array_equal(received[agent]["image"], sent[agent]["image"]), agent
        assert {k: v for k, v in received[agent].items() if k != "image"} == {
            k: v for k, v in sent[agent].items() if k != "image"}
    seen[:] = 0  # the policy holds a copy: the next step's images do not change it
    images.pack({"a": _observation(seen, CameraChoice.TOP)})
    assert received["a"]["image"].any()


def test_what_is_not_a_camera_image_is_sent_as_it_is() -> None:
    images = SharedImages(1)
    frames = _handed_over(images)
    odd = {"a": _observation(np.zeros((4, 4, 3), np.uint8), CameraChoice.TOP),
           "b": _observation(np.zeros(IMAGE_SHAPE, np.uint8), CameraChoice.TOP),  # no slot left for it
           "c": "not an observation"}
    packed = images.pack(odd)
    assert packed["a"] is odd["a"] and packed["b"] is odd["b"] and packed["c"] == "not an observation"
    assert unpack(frames, packed) == packed
    assert frames.shape == (1, *IMAGE_SHAPE)  # a controller maps its own robots' slots, no more


def _open_image_files() -> int:
    """How many descriptors of this process lead to image slots (0 where /proc is missing)."""
    if not os.path.isdir("/proc/self/fd"):
        return 0
    count = 0
    for entry in os.listdir("/proc/self/fd"):
        try:
            count += "robot-images" in os.readlink(f"/proc/self/fd/{entry}")
        except OSError:
            continue
    return count


def test_the_slots_descriptor_is_closed_once_handed_over() -> None:
    images = SharedImages(2)
    held = _open_image_files()
    frames = _handed_over(images)
    assert _open_image_files() == held - 1 or not held  # its descriptor is gone; the mappings stay
    images.pack({"a": {"image": np.full(IMAGE_SHAPE, 7, np.uint8), "camera": int(CameraChoice.TOP)}})
    assert frames[0].min() == 7
    images.close()
    images.close()
