"""The one bounded reader of small input files (scenarios.common.untrusted.read_small_file)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from scenarios.common.untrusted import SmallFileError, read_small_file


def test_a_small_regular_file_is_read_whole(tmp_path: Path) -> None:
    (tmp_path / "f").write_bytes(b"abc")
    assert read_small_file(tmp_path / "f", 3) == b"abc"


@pytest.mark.parametrize("name", ["nowhere", "dir", "link_to_nowhere"])
def test_no_regular_file_is_missing(tmp_path: Path, name: str) -> None:
    (tmp_path / "dir").mkdir()
    os.symlink(tmp_path / "nowhere", tmp_path / "link_to_nowhere")
    with pytest.raises(SmallFileError, match="^not an existing regular file$") as caught:
        read_small_file(tmp_path / name, 10)
    assert caught.value.missing and not caught.value.too_big


def test_a_bigger_file_is_refused_by_its_size(tmp_path: Path) -> None:
    (tmp_path / "f").write_bytes(b"abcd")
    with pytest.raises(SmallFileError, match="^4 bytes$") as caught:
        read_small_file(tmp_path / "f", 3)
    assert caught.value.too_big and not caught.value.missing


def test_a_name_too_long_is_the_systems_error(tmp_path: Path) -> None:
    with pytest.raises(SmallFileError, match="name too long") as caught:
        read_small_file(tmp_path / ("n" * 300), 10)
    assert not caught.value.missing and not caught.value.too_big


@pytest.mark.parametrize("kind", ["fifo", "zero", "null"])
def test_a_pipe_or_a_device_is_refused_before_it_is_opened(tmp_path: Path, kind: str) -> None:
    path = tmp_path / "f"
    if kind == "fifo":
        os.mkfifo(path)  # opening it to read would wait for a writer
    else:
        path.symlink_to(f"/dev/{kind}")  # /dev/zero never ends
    with pytest.raises(SmallFileError, match="^not an existing regular file$"):
        read_small_file(path, 10)
