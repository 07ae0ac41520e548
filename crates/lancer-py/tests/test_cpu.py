"""The import-time CPU check (lancer._cpu), with made-up CPUs, and the real library's mark."""

import pytest

from lancer import _cpu


def test_an_old_cpu_is_refused_with_advice():
    with pytest.raises(ImportError) as caught:
        _cpu.check(flags={"sse2", "avx"}, needs_v3=lambda: True)
    message = str(caught.value)
    assert "x86-64-v3" in message and "AVX2 and FMA" in message
    assert 'RUSTFLAGS="-C target-cpu=x86-64"' in message


def test_a_v3_cpu_or_a_baseline_build_passes():
    _cpu.check(flags={"avx2", "fma", "sse2"}, needs_v3=lambda: True)
    _cpu.check(flags={"sse2"}, needs_v3=lambda: False)


def test_cpu_flags_are_read_from_cpuinfo(tmp_path):
    info = tmp_path / "cpuinfo"
    info.write_text("processor\t: 0\nmodel name\t: Test\nflags\t\t: fpu sse2 avx2 fma\n\n")
    assert _cpu.cpu_flags(str(info)) == {"fpu", "sse2", "avx2", "fma"}
    assert _cpu.cpu_flags(str(tmp_path / "missing")) is None


def test_the_built_library_is_marked_x86_64_v3():
    # The workspace's .cargo/config.toml builds for x86-64-v3, and so does maturin's build.
    assert _cpu.native_needs_x86_64_v3() is True
