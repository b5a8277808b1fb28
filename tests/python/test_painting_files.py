"""The layered-painting reader's messages (the add-on's painting_files, which needs no Blender): a
truncated file is called damaged, a missing file not found, a missing layer image named once."""
import os
import re
import zipfile

import pytest

import painting_attacks

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLE = os.path.join(ROOT, "examples", "sprites", "character.ora")


@pytest.fixture(scope="module")
def reader():
    return painting_attacks.reader()


def test_the_example_reads_bottom_layer_first(reader):
    names = [layer.name for layer in reader.read_painting(EXAMPLE)]
    assert names[0] == "forearm_l" and names[-1] == "forearm_r" and len(names) == 10


def test_a_truncated_file_is_called_damaged(reader, tmp_path):
    cut = tmp_path / "cut.ora"
    data = open(EXAMPLE, "rb").read()
    cut.write_bytes(data[:len(data) * 2 // 3])
    with pytest.raises(ValueError) as e:
        reader.read_painting(str(cut))
    message = str(e.value)
    assert re.match(r"'.*cut\.ora' is damaged \(it ends too early: .*\): save or copy it again",
                    message), message
    assert "not an OpenRaster" not in message


def test_a_missing_file_is_called_not_found(reader, tmp_path):
    with pytest.raises(ValueError) as e:
        reader.read_painting(str(tmp_path / "gone.ora"))
    assert re.fullmatch(r"'.*gone\.ora' not found: check the file's name and folder", str(e.value))
    assert "Errno" not in str(e.value)


def test_a_file_that_is_no_zip_is_not_an_openraster_file(reader, tmp_path):
    text = tmp_path / "notes.ora"
    text.write_text("just some words, long enough to be read as a file")
    with pytest.raises(ValueError, match=r"'.*notes\.ora' is not an OpenRaster file \("):
        reader.read_painting(str(text))


def test_a_missing_layer_image_is_named_with_single_quotes(reader, tmp_path):
    broken = tmp_path / "broken.ora"
    with zipfile.ZipFile(EXAMPLE) as src, zipfile.ZipFile(broken, "w") as dst:
        for item in src.namelist():
            if item != "data/forearm_r.png":
                dst.writestr(item, src.read(item))
    with pytest.raises(ValueError) as e:
        reader.read_painting(str(broken))
    assert re.fullmatch(r"'.*broken\.ora': layer 'forearm_r': its image 'data/forearm_r\.png' "
                        r"is missing", str(e.value)), str(e.value)
    assert "''" not in str(e.value)


def test_a_file_without_stack_xml_says_so(reader, tmp_path):
    bare = tmp_path / "bare.ora"
    with zipfile.ZipFile(EXAMPLE) as src, zipfile.ZipFile(bare, "w") as dst:
        dst.writestr("mimetype", src.read("mimetype"))
    with pytest.raises(ValueError, match=r"'.*bare\.ora' is not an OpenRaster file: it has no "
                       r"stack\.xml$"):
        reader.read_painting(str(bare))
