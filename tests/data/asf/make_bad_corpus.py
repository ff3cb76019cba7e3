#!/usr/bin/env python3
"""Writes the malformed ASF/AMC corpus in bad/ and its manifest bad/expected.tsv.

Each case is a small valid skeleton or motion with one defect; the manifest gives the file, the
expected `line:col` of the error and a substring of its message. An .amc case is read with the
valid skeleton good.asf; an .asf case is read on its own. Run from this folder: ./make_bad_corpus.py
"""
import os

GOOD_ASF = """# a small Acclaim skeleton
:version 1.10
:name test
:units
  mass 1.0
  length 0.45
  angle deg
:root
   order TX TY TZ RX RY RZ
   axis XYZ
   position 0 0 0
   orientation 0 0 0
:bonedata
  begin
     id 1
     name lfemur
     direction 0 -1 0
     length 7
     axis 0 0 20 XYZ
    dof rx ry rz
    limits (-160.0 20.0)
           (-70.0 70.0)
           (-60.0 70.0)
  end
  begin
     id 2
     name ltibia
     direction 0 -1 0
     length 7
     axis 0 0 20 XYZ
    dof rx
  end
:hierarchy
  begin
    root lfemur
    lfemur ltibia
  end
"""

GOOD_AMC = """:FULLY-SPECIFIED
:DEGREES
1
root 0 17 0 0 0 0
lfemur 10 0 0
ltibia 20
2
root 0 17 0.1 0 0 0
lfemur 11 0 0
ltibia 21
"""


def replace(text, old, new):
    assert old in text, old
    return text.replace(old, new, 1)


ASF_CASES = {
    "empty.asf": ("", "1:1", "empty ASF file"),
    "unknown_section.asf": (replace(GOOD_ASF, ":name test", ":nmae test"), "3:1", "unknown section ':nmae'"),
    "not_a_section.asf": (replace(GOOD_ASF, ":version 1.10", "version 1.10"), "2:1", "expected a section keyword"),
    "bad_length_unit.asf": (replace(GOOD_ASF, "length 0.45", "length -1"), "6:10", "the length unit must be > 0"),
    "bad_angle_unit.asf": (replace(GOOD_ASF, "angle deg", "angle grad"), "7:9", "angle unit 'grad' is not deg or rad"),
    "bad_root_order.asf": (replace(GOOD_ASF, "order TX TY TZ RX RY RZ", "order TX TY TZ RX RY RW"), "9:25", "unknown dof 'RW'"),
    "bad_axis_order.asf": (replace(GOOD_ASF, "axis 0 0 20 XYZ\n    dof rx ry rz", "axis 0 0 20 XXZ\n    dof rx ry rz"), "19:18", "expected an axis order such as XYZ"),
    "corrupt_number.asf": (replace(GOOD_ASF, "length 7\n     axis 0 0 20 XYZ\n    dof rx ry", "length 7x\n     axis 0 0 20 XYZ\n    dof rx ry"), "18:13", "expected a number, got '7x'"),
    "huge_number.asf": (replace(GOOD_ASF, "direction 0 -1 0\n     length 7\n     axis 0 0 20 XYZ\n    dof rx\n", "direction 0 -1e999 0\n     length 7\n     axis 0 0 20 XYZ\n    dof rx\n"), "28:18", "out of range"),
    "missing_value.asf": (replace(GOOD_ASF, "direction 0 -1 0\n     length 7\n     axis 0 0 20 XYZ\n    dof rx ry", "direction 0 -1\n     length 7\n     axis 0 0 20 XYZ\n    dof rx ry"), "17:18", "'direction' takes 3 value(s), got 2"),
    "duplicate_dof.asf": (replace(GOOD_ASF, "dof rx ry rz", "dof rx ry rx"), "20:15", "dof 'rx' listed twice"),
    "translation_dof.asf": (replace(GOOD_ASF, "dof rx\n", "dof tx\n"), "31:9", "translation dofs on a bone are not supported"),
    "bone_without_end.asf": (replace(GOOD_ASF, "           (-60.0 70.0)\n  end\n", "           (-60.0 70.0)\n"), "24:3", "'begin' inside a bone"),
    "bone_without_name.asf": (replace(GOOD_ASF, "     name ltibia\n", ""), "25:3", "bone without a name"),
    "duplicate_bone.asf": (replace(GOOD_ASF, "name ltibia", "name lfemur"), "25:3", "bone 'lfemur' is declared twice"),
    "unknown_bone_entry.asf": (replace(GOOD_ASF, "     id 2\n", "     idx 2\n"), "26:6", "unknown bone entry 'idx'"),
    "unknown_hierarchy_bone.asf": (replace(GOOD_ASF, "lfemur ltibia\n  end", "lfemur lknee\n  end"), "36:12", "unknown bone 'lknee' in :hierarchy"),
    "two_parents.asf": (replace(GOOD_ASF, "root lfemur\n", "root lfemur ltibia\n"), "36:12", "bone 'ltibia' has two parents"),
    "unconnected_bone.asf": (replace(GOOD_ASF, "    lfemur ltibia\n", ""), "25:1", "bone 'ltibia' is not connected to the root"),
    "no_hierarchy.asf": (GOOD_ASF[: GOOD_ASF.index(":hierarchy")], "32:1", "no :hierarchy section"),
    "hierarchy_without_end.asf": (replace(GOOD_ASF, "    lfemur ltibia\n  end\n", "    lfemur ltibia\n"), "33:1", ":hierarchy without 'end'"),
    "binary_garbage.asf": ("\x01\x02\x03garbage\n", "1:1", "not a text file"),
}

AMC_CASES = {
    "empty.amc": ("", "1:1", "no frames"),
    "unknown_keyword.amc": (replace(GOOD_AMC, ":DEGREES", ":GRADIANS"), "2:1", "unknown AMC keyword ':GRADIANS'"),
    "values_before_frame.amc": (replace(GOOD_AMC, "1\nroot", "root"), "3:1", "expected a frame number, got 'root'"),
    "frame_gap.amc": (replace(GOOD_AMC, "\n2\n", "\n3\n"), "7:1", "frame number 3 where 2 is expected"),
    "unknown_bone.amc": (replace(GOOD_AMC, "ltibia 20", "lknee 20"), "6:1", "unknown bone 'lknee'"),
    "too_many_values.amc": (replace(GOOD_AMC, "lfemur 10 0 0", "lfemur 10 0 0 4"), "5:15", "'lfemur' takes 3 value(s), got 4"),
    "too_few_values.amc": (replace(GOOD_AMC, "root 0 17 0 0 0 0", "root 0 17 0 0 0"), "4:15", "'root' takes 6 value(s), got 5"),
    "corrupt_number.amc": (replace(GOOD_AMC, "lfemur 11 0 0", "lfemur 11 0 O"), "9:13", "expected a number, got 'O'"),
    "nan.amc": (replace(GOOD_AMC, "ltibia 21", "ltibia nan"), "10:8", "out of range"),
    "repeated_bone.amc": (replace(GOOD_AMC, "ltibia 20\n", "ltibia 20\nltibia 20\n"), "7:1", "'ltibia' appears twice in frame 1"),
    "missing_bone.amc": (replace(GOOD_AMC, "ltibia 20\n", ""), "6:1", "frame 1 has no line for bone 'ltibia'"),
    "missing_bone_last_frame.amc": (replace(GOOD_AMC, "ltibia 21\n", ""), "9:1", "frame 2 has no line for bone 'ltibia'"),
    "keyword_after_frames.amc": (GOOD_AMC + ":DEGREES\n", "11:1", "keyword ':DEGREES' after the first frame"),
}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = os.path.join(here, "bad")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "good.asf"), "w", newline="\n") as f:
        f.write(GOOD_ASF)
    with open(os.path.join(out, "good.amc"), "w", newline="\n") as f:
        f.write(GOOD_AMC)
    rows = ["# file\tline:col\tmessage substring   (generated by ../make_bad_corpus.py; .amc files use good.asf)"]
    for name, (text, where, message) in sorted({**ASF_CASES, **AMC_CASES}.items()):
        with open(os.path.join(out, name), "w", newline="\n") as f:
            f.write(text)
        rows.append(f"{name}\t{where}\t{message}")
    with open(os.path.join(out, "expected.tsv"), "w", newline="\n") as f:
        f.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
