"""The ctypes mirror (python/quarry/_abi.py) is include/quarry/quarry.h: every struct of the header
with the same fields in the same order, the sizes and offsets a C compiler gives them
(tests/python/abi_layout.c, built by CMake), every constant with its value, and a prototype for
every function the header declares."""

import ctypes
import json
import os
import re
import subprocess
import unittest

from quarry import _abi

SOURCE = os.environ.get("QUARRY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
HEADER = os.path.join(SOURCE, "include", "quarry", "quarry.h")


def header_text():
    with open(HEADER, encoding="utf-8") as f:
        text = f.read()
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)  # comments hold words that look like code
    return re.sub(r"//[^\n]*", "", text)


def header_structs(text):
    """{struct name: [field names in order]} of every `typedef struct quarry_x {...} quarry_x;`."""
    structs = {}
    for name, body in re.findall(r"typedef struct (quarry_\w+) \{(.*?)\} \1;", text, flags=re.S):
        structs[name] = re.findall(r"(\w+)\s*(?:\[\d+\])?\s*;", body)
    return structs


def header_constants(text):
    """Names of every enum constant and QUARRY_ABI_MAJOR / MINOR."""
    names = set()
    for body in re.findall(r"enum \{(.*?)\};", text, flags=re.S):
        names.update(re.findall(r"\b(QUARRY_\w+)\s*=", body))
    return names | {"QUARRY_ABI_MAJOR", "QUARRY_ABI_MINOR"}


def header_functions(text):
    return set(re.findall(r"QUARRY_API\s+[\w\s\*]+?\b(quarry_\w+)\s*\(", text))


def mirrored_constants():
    values = {"QUARRY_ABI_MAJOR": _abi.ABI_MAJOR, "QUARRY_ABI_MINOR": _abi.ABI_MINOR}
    for enum_type, prefix in _abi.ENUM_PREFIXES.items():
        for member in enum_type:
            values[prefix + member.name] = int(member)
    return values


class Mirror(unittest.TestCase):
    def setUp(self):
        self.text = header_text()

    def test_every_struct_has_the_headers_fields_in_order(self):
        structs = header_structs(self.text)
        mirrored = {s.__name__: [f for f, _ in s._fields_] for s in _abi.STRUCTS}
        self.assertEqual(set(structs), set(mirrored), "structs of quarry.h and of _abi.STRUCTS")
        for name, fields in structs.items():
            self.assertEqual(mirrored[name], fields, name)
        print("\n%d structs, %d fields mirrored" % (len(structs), sum(map(len, structs.values()))))

    def test_every_constant_has_the_headers_value(self):
        names = header_constants(self.text)
        values = mirrored_constants()
        self.assertEqual(names, set(values), "constants of quarry.h and of the mirror's enums")

    def test_every_function_has_a_prototype(self):
        self.assertEqual(header_functions(self.text), set(_abi.PROTOTYPES))

    def test_sizes_offsets_and_values_are_the_c_compilers(self):
        program = os.environ.get("QUARRY_ABI_LAYOUT")
        if not program:
            self.skipTest(
                "QUARRY_ABI_LAYOUT (the abi_layout program) is not set: run through ctest"
            )
        layout = json.loads(
            subprocess.run([program], check=True, capture_output=True, text=True).stdout
        )
        checked = 0
        for struct in _abi.STRUCTS:
            name = struct.__name__
            self.assertEqual(ctypes.sizeof(struct), layout["size:" + name], "sizeof(%s)" % name)
            for field, field_type in struct._fields_:
                key = "%s.%s" % (name, field)
                self.assertEqual(
                    getattr(struct, field).offset, layout["offset:" + key], "offsetof " + key
                )
                self.assertEqual(ctypes.sizeof(field_type), layout["size:" + key], "sizeof " + key)
                checked += 1
        values = mirrored_constants()
        constants = {
            key[len("constant:") :]: value
            for key, value in layout.items()
            if key.startswith("constant:")
        }
        self.assertEqual(constants, values)
        print(
            "\nthe C compiler agrees: %d struct sizes, %d field offsets and sizes, %d constants"
            % (len(_abi.STRUCTS), checked, len(constants))
        )


if __name__ == "__main__":
    unittest.main()
