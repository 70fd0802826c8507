"""The installed extension carries no debug info (the wheel is built stripped): its ELF file
has no .debug_* sections and no symbol table beyond the dynamic one."""

import pathlib
import struct
import sys

import pytest

import spheresweep._native as native


def section_names(path):
    """The section names of a 64-bit little-endian ELF file."""
    data = pathlib.Path(path).read_bytes()
    assert data[:4] == b"\x7fELF" and data[4] == 2 and data[5] == 1, "a 64-bit little-endian ELF"
    shoff, = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x3A)
    headers = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + k * shentsize) for k in range(shnum)]
    strtab = headers[shstrndx]
    names = data[strtab[4]:strtab[4] + strtab[5]]
    return [names[h[0]:names.index(b"\0", h[0])].decode() for h in headers]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="ELF")
def test_the_installed_module_has_no_debug_info():
    names = section_names(native.__file__)
    assert ".text" in names and ".dynsym" in names  # the reader reads this file
    assert not [n for n in names if n.startswith(".debug")], names
    assert ".symtab" not in names
    assert pathlib.Path(native.__file__).stat().st_size < 8 << 20
