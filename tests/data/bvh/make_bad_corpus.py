#!/usr/bin/env python3
"""Writes the malformed-BVH corpus in bad/ and its manifest bad/expected.tsv.

Each corpus file is a small valid clip (BASE below) with one defect. The manifest says, per file,
where the reader must report it (`line:col`, or `line:*` when the column is not pinned) and a
substring its one-line message must contain; tests/unit/bvh/bvh_bad_input_test.cpp checks both
and that every .bvh in bad/ has a manifest entry. Re-run this script after editing it:
    python3 tests/data/bvh/make_bad_corpus.py
"""
import os
import random

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bad")

# Line numbers of BASE: 1 HIERARCHY, 2 ROOT, 4 OFFSET, 5 CHANNELS, 6 JOINT Chest, 8 OFFSET,
# 9 CHANNELS, 10 End Site, 12 OFFSET, 16 MOTION, 17 Frames, 18 Frame Time, 19-21 rows.
BASE = """HIERARCHY
ROOT Hips
{
\tOFFSET 0.0 0.0 0.0
\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
\tJOINT Chest
\t{
\t\tOFFSET 0.0 10.0 0.0
\t\tCHANNELS 3 Zrotation Xrotation Yrotation
\t\tEnd Site
\t\t{
\t\t\tOFFSET 0.0 5.0 0.0
\t\t}
\t}
}
MOTION
Frames: 3
Frame Time: 0.033333
0 90 0 0 0 0 0 0 0
1 90 0 10 0 0 5 0 0
2 90 0 20 0 0 10 0 0
"""

HEADER = BASE[: BASE.index("MOTION")]


def sub(old, new, count=1):
    assert old in BASE, old
    return BASE.replace(old, new, count)


def cut(marker, keep_marker=True):
    i = BASE.index(marker)
    return BASE[: i + (len(marker) if keep_marker else 0)]


rng = random.Random(20261123)
garbage = b"\x89PNG\r\n\x1a\n" + bytes(rng.randrange(256) for _ in range(600))
c3d_like = bytes([0x02, 0x50, 0x1A, 0x00]) + bytes(rng.randrange(256) for _ in range(1020))

# name -> (content, "line:col", message substring)
CASES = {
    "empty.bvh": ("", "1:1", "empty file"),
    "whitespace_only.bvh": ("\n  \r\n\t\n", "4:1", "empty file"),
    "binary_garbage.bvh": (garbage, "1:1", "not a BVH file: expected 'HIERARCHY'"),
    "c3d_renamed.bvh": (c3d_like, "1:1", "not a BVH file"),
    "utf16.bvh": (BASE.encode("utf-16"), "1:1", "not a BVH file"),
    "no_root.bvh": ("HIERARCHY\nMOTION\nFrames: 0\nFrame Time: 0.1\n", "2:1", "MOTION before any ROOT"),
    "root_without_name.bvh": (sub("ROOT Hips", "ROOT"), "2:1", "ROOT without a name"),
    "missing_brace_after_root.bvh": (sub("ROOT Hips\n{", "ROOT Hips\n\tOFFSET"), "3:2", "expected '{' after ROOT 'Hips'"),
    "unbalanced_missing_close.bvh": (sub("\t\t}\n\t}\n}\n", "\t\t}\n\t}\n"), "15:1",
                                     "unbalanced braces: joint 'Hips' opened at line 2 is not closed before MOTION"),
    "unbalanced_extra_close.bvh": (sub("}\nMOTION", "}\n}\nMOTION"), "16:1", "'}' without a matching '{'"),
    "unknown_keyword.bvh": (sub("\t\tOFFSET 0.0 10.0 0.0", "\t\tOFSET 0.0 10.0 0.0"), "8:3", "unknown keyword 'OFSET'"),
    "bad_channel_name.bvh": (sub("CHANNELS 3 Zrotation Xrotation", "CHANNELS 3 Zrotation Wrotation"), "9:24",
                             "unknown channel 'Wrotation'"),
    "absurd_channel_count.bvh": (sub("CHANNELS 3 Zrotation", "CHANNELS 999999999 Zrotation"), "9:12",
                                 "CHANNELS count must be an integer from 0 to 6"),
    "duplicate_channel.bvh": (sub("CHANNELS 3 Zrotation Xrotation", "CHANNELS 3 Zrotation Zrotation"), "9:24",
                              "channel Zrotation listed twice in joint 'Chest'"),
    "offset_not_number.bvh": (sub("OFFSET 0.0 10.0 0.0", "OFFSET 0.0 ten 0.0"), "8:14",
                              "expected a number for OFFSET, found 'ten'"),
    "offset_nan.bvh": (sub("OFFSET 0.0 10.0 0.0", "OFFSET 0.0 nan 0.0"), "8:14", "OFFSET value 'nan' is not a finite number"),
    "offset_short.bvh": (sub("OFFSET 0.0 10.0 0.0", "OFFSET 0.0 10.0"), "9:3", "expected a number for OFFSET, found 'CHANNELS'"),
    "missing_offset.bvh": (sub("\t\tOFFSET 0.0 10.0 0.0\n", ""), "6:1", "joint 'Chest' has no OFFSET"),
    "second_offset.bvh": (sub("\t\tOFFSET 0.0 10.0 0.0\n", "\t\tOFFSET 0.0 10.0 0.0\n\t\tOFFSET 1 2 3\n"), "9:3",
                          "second OFFSET in joint 'Chest'"),
    "end_site_without_offset.bvh": (sub("\t\t\tOFFSET 0.0 5.0 0.0\n", ""), "12:3", "expected OFFSET in End Site, found '}'"),
    "end_without_site.bvh": (sub("End Site", "End Point"), "10:7", "expected 'Site' after 'End', found 'Point'"),
    "missing_frames.bvh": (sub("Frames: 3\n", ""), "17:1", "expected 'Frames:', found 'Frame'"),
    "frames_negative.bvh": (sub("Frames: 3", "Frames: -5"), "17:9", "frame count '-5' is not a non-negative integer"),
    "frames_not_number.bvh": (sub("Frames: 3", "Frames: many"), "17:9", "frame count 'many' is not a non-negative integer"),
    "frames_overflow.bvh": (sub("Frames: 3", "Frames: 99999999999999999999"), "17:9", "is absurd"),
    "frames_absurd.bvh": (sub("Frames: 3", "Frames: 2000000000"), "22:1",
                          "the file ends after 3 frames but 'Frames:' at line 17 declares 2000000000 "
                          "(more than a file of this size can hold)"),
    "frames_trailing_text.bvh": (sub("Frames: 3", "Frames: 3 frames"), "17:11", "unexpected text after the frame count"),
    "missing_frame_time.bvh": (sub("Frame Time: 0.033333\n", ""), "18:1", "expected 'Frame Time:', found '0'"),
    "frame_time_negative.bvh": (sub("Frame Time: 0.033333", "Frame Time: -0.1"), "18:13", "must be a finite, non-negative"),
    "frame_time_nan.bvh": (sub("Frame Time: 0.033333", "Frame Time: NaN"), "18:13", "must be a finite, non-negative"),
    "frame_time_text.bvh": (sub("Frame Time: 0.033333", "Frame Time: fast"), "18:13", "expected the frame time in seconds"),
    "fewer_rows.bvh": (sub("Frames: 3", "Frames: 5"), "22:1", "the file ends after 3 frames but 'Frames:' at line 17 declares 5"),
    "short_row.bvh": (sub("1 90 0 10 0 0 5 0 0", "1 90 0 10 0 0 5 0"), "20:18", "frame 1 has 8 values, expected 9"),
    "long_row.bvh": (sub("1 90 0 10 0 0 5 0 0", "1 90 0 10 0 0 5 0 0 7"), "20:21", "frame 1 has more than 9 values"),
    "corrupt_number.bvh": (sub("1 90 0 10 0 0 5 0 0", "1 90 0 1.0.0 0 0 5 0 0"), "20:8",
                           "invalid number '1.0.0' in frame 1 (column 4, Hips Zrotation)"),
    "number_with_letters.bvh": (sub("2 90 0 20 0 0 10 0 0", "2 90 0 20 0 0 10 0x1F 0"), "21:18", "invalid number '0x1F'"),
    "nan_value.bvh": (sub("1 90 0 10 0 0 5 0 0", "1 90 0 10 nan 0 5 0 0"), "20:11",
                      "value 'nan' is not a finite number in frame 1 (column 5, Hips Xrotation)"),
    "inf_value.bvh": (sub("2 90 0 20 0 0 10 0 0", "2 90 0 20 0 0 10 -inf 0"), "21:18", "value '-inf' is not a finite number"),
    "overflow_value.bvh": (sub("0 90 0 0 0 0 0 0 0", "0 90 1e999 0 0 0 0 0 0"), "19:6", "value '1e999' is not a finite number"),
    "nul_byte.bvh": (sub("1 90 0 10 0 0 5 0 0", "1 90 0 10 0 0 \x00 0 0"), "20:15", "invalid number '\\x00'"),
    "no_channels.bvh": (BASE.replace("CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation", "CHANNELS 0")
                        .replace("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 0"), "19:1",
                        "motion data found but the hierarchy declares no channels"),
    "text_after_frame_time.bvh": (sub("Frame Time: 0.033333", "Frame Time: 0.033333 s"), "18:22", "unexpected text after the frame time"),
    # Truncations at several points of the file.
    "truncated_after_hierarchy.bvh": ("HIERARCHY\n", "2:1", "unexpected end of file: expected ROOT"),
    "truncated_after_root_name.bvh": (cut("ROOT Hips\n"), "3:1", "expected '{' after ROOT 'Hips', found end of file"),
    "truncated_in_offset.bvh": (cut("\t\tOFFSET 0.0 10"), "8:16", "expected a number for OFFSET, found end of file"),
    "truncated_in_channels.bvh": (cut("CHANNELS 6 Xposition Yposition"), "5:32",
                                  "unexpected end of file: CHANNELS at line 5 declares 6 channels, found 2"),
    "truncated_in_joint.bvh": (cut("\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n"), "10:1",
                               "unexpected end of file inside joint 'Chest' (line 6): missing '}'"),
    "truncated_in_end_site.bvh": (cut("\t\t\tOFFSET 0.0 5.0 0.0\n"), "13:1", "expected '}' to close the End Site opened at line 10"),
    "truncated_before_motion.bvh": (HEADER, "16:1", "unexpected end of file: expected MOTION"),
    "truncated_after_motion.bvh": (cut("MOTION\n"), "17:1", "expected 'Frames:', found end of file"),
    "truncated_after_frames.bvh": (cut("Frames: 3\n"), "18:1", "expected 'Frame Time:', found end of file"),
    "truncated_in_frame_time.bvh": (cut("Frame Time:"), "18:12", "expected the frame time in seconds after 'Frame Time:', found end of file"),
    "truncated_before_rows.bvh": (cut("Frame Time: 0.033333\n"), "19:1", "the file ends after 0 frames but 'Frames:' at line 17 declares 3"),
    "truncated_mid_row.bvh": (cut("1 90 0 10"), "20:10", "frame 1 has 4 values, expected 9"),
    "truncated_after_row.bvh": (cut("1 90 0 10 0 0 5 0 0\n"), "21:1", "the file ends after 2 frames but 'Frames:' at line 17 declares 3"),
}


def main():
    os.makedirs(HERE, exist_ok=True)
    for f in os.listdir(HERE):
        if f.endswith(".bvh"):
            os.remove(os.path.join(HERE, f))
    with open(os.path.join(HERE, "expected.tsv"), "w") as manifest:
        manifest.write("# file\tline:col\tmessage substring   (generated by ../make_bad_corpus.py)\n")
        for name, (content, where, message) in sorted(CASES.items()):
            data = content if isinstance(content, bytes) else content.encode("latin-1")
            with open(os.path.join(HERE, name), "wb") as out:
                out.write(data)
            manifest.write(f"{name}\t{where}\t{message}\n")


if __name__ == "__main__":
    main()
