#!/usr/bin/env python3
"""Pack a Debian build of isg for a GPU machine that has neither Debian's libraries nor their
package registry (the device machines lent to sessions: an NVIDIA driver, no OpenImageIO):

    python3 scripts/device/bundle.py BUILD OUT.tar.xz

The tarball holds bin/ (the isg binaries, oiiotool, every tests/gpu binary), B/ (cli/ and
tools/synth/ as bench/*.py expect a build), lib/ (every library they load but glibc's, the
Vulkan loader and libglvnd, which NVIDIA's ICD needs) and layer/ (the Khronos validation layer).
OpenImageIO's Debian build links the libraries of every format plugin it has (ffmpeg, OpenVDB,
GDAL through OpenCV, DCMTK, ...: 350 MB); isg reads and writes only EXR, so those are replaced by
stubs that export the symbols the kept libraries import (each function returns a pointer to
zeros: OIIO's start-up calls a few, e.g. DCMTK's registration, and reads version strings).
Packed: about 14 MB. scripts/device/check.sh runs it there."""
import os, re, shutil, subprocess, sys, tempfile

build, out = sys.argv[1], os.path.abspath(sys.argv[2])
STUB = re.compile(r'^lib(opencv_|dcm|of|av|swscale|swresample|heif|openvdb|raw_r|gif|openjp2|webp|'
                  r'freetype|tiff|png16|jpeg)')
GLIBC = re.compile(r'^(libc\.so|libm\.so|libpthread|libdl\.so|librt\.so|ld-linux|libresolv)')
LIBDIRS = ['/lib/x86_64-linux-gnu', '/usr/lib/x86_64-linux-gnu']


def run(*a):
    return subprocess.run(a, check=True, capture_output=True, text=True).stdout


def needed(path):
    return re.findall(r'\(NEEDED\).*\[(.*)\]', run('readelf', '-dW', path))


def where(name):
    for d in LIBDIRS:
        if os.path.exists(os.path.join(d, name)):
            return os.path.realpath(os.path.join(d, name))
    sys.exit(f'bundle.py: {name} not found in {LIBDIRS}')


def dynsyms(path):
    rows = [l.split() for l in run('readelf', '--dyn-syms', '-W', path).splitlines()]
    return [f for f in rows if len(f) >= 8 and f[0].endswith(':')]


def stub(name, real, imports, dst, tmp):
    """A library named `name` exporting what `imports` takes from `real`, with its versions."""
    asm, vers = ['.bss\n.balign 64\n__isg_zero:\n.zero 65536'], {}
    for f in dynsyms(real):
        sym = f[7].split('@')[0]
        if f[6] == 'UND' or f[4] == 'LOCAL' or sym not in imports or f[3] not in ('FUNC', 'IFUNC', 'OBJECT'):
            continue
        if f[3] == 'OBJECT':
            size = max(int(f[2], 0), 1)
            asm.append(f'.data\n.globl "{sym}"\n.type "{sym}",@object\n.size "{sym}",{size}\n"{sym}":\n.zero {size}')
        else:
            asm.append(f'.text\n.globl "{sym}"\n.type "{sym}",@function\n"{sym}":\nleaq __isg_zero(%rip),%rax\nret')
        vers.setdefault(f[7].split('@')[-1] if '@' in f[7] else None, []).append(sym)
    named = [k for k in vers if k]
    if named:  # unversioned references bind to any version: give them the first
        vers[named[0]] += vers.pop(None, [])
        script = [f'{k} {{ global: {"; ".join(vers[k])}; {"local: *; " if i == len(named) - 1 else ""}}};'
                  for i, k in enumerate(named)]
    else:
        script = ['{ global: ' + '; '.join(vers.get(None, ['__isg_stub'])) + '; local: *; };']
    s, v = os.path.join(tmp, name + '.s'), os.path.join(tmp, name + '.ver')
    open(s, 'w').write('\n'.join(asm) + '\n')
    open(v, 'w').write('\n'.join(script) + '\n')
    run('gcc', '-shared', '-nostdlib', '-o', os.path.join(dst, name), s, f'-Wl,-soname,{name}',
        f'-Wl,--version-script,{v}')


def main():
    tmp = tempfile.mkdtemp(prefix='isg-bundle-')
    for d in ('bin', 'lib', 'layer', 'B/cli', 'B/tools/synth'):
        os.makedirs(os.path.join(tmp, d))
    gpu_tests = os.path.join(build, 'tests', 'gpu')
    bins = [os.path.join(gpu_tests, t) for t in sorted(os.listdir(gpu_tests)) if t.startswith('isg_') and t.endswith('_tests')]
    bins.append(shutil.which('oiiotool'))
    for b in bins:
        shutil.copy(b, os.path.join(tmp, 'bin'))
    for b in ('isg', 'isg-exrcheck'):
        shutil.copy(os.path.join(build, 'cli', b), os.path.join(tmp, 'B', 'cli'))
    shutil.copy(os.path.join(build, 'tools', 'synth', 'isg-synth'), os.path.join(tmp, 'B', 'tools', 'synth'))
    elves = bins + [os.path.join(build, 'cli', 'isg'), os.path.join(build, 'tools', 'synth', 'isg-synth')]
    layer = os.path.join(LIBDIRS[1], 'libVkLayer_khronos_validation.so')
    keep, stubs, todo = {}, {}, [n for e in elves + [layer] for n in needed(e)]
    todo += ['libvulkan.so.1', 'libGLX.so.0', 'libGLdispatch.so.0', 'libEGL.so.1', 'libOpenGL.so.0']
    while todo:
        n = todo.pop()
        if n in keep or n in stubs or GLIBC.match(n):
            continue
        if STUB.match(n):
            stubs[n] = where(n)
            continue
        keep[n] = where(n)
        todo += needed(keep[n])
    imports = {f[7].split('@')[0] for p in list(keep.values()) + elves for f in dynsyms(p) if f[6] == 'UND'}
    for n, p in keep.items():
        shutil.copy(p, os.path.join(tmp, 'lib', n))
    for n, p in stubs.items():
        stub(n, p, imports, os.path.join(tmp, 'lib'), tmp)
    shutil.copy(layer, os.path.join(tmp, 'layer'))
    manifest = open('/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json').read()
    manifest = re.sub(r'"library_path":\s*"[^"]*"', '"library_path": "./libVkLayer_khronos_validation.so"', manifest)
    open(os.path.join(tmp, 'layer', 'VkLayer_khronos_validation.json'), 'w').write(manifest)
    subprocess.run(f'tar cf - bin lib layer B | xz -T0 -6 > "{out}"', shell=True, check=True, cwd=tmp)
    shutil.rmtree(tmp)
    print(f'{out}: {os.path.getsize(out) / 2**20:.1f} MiB; {len(keep)} libraries kept, {len(stubs)} stubbed: '
          + ' '.join(sorted(stubs)))


main()
