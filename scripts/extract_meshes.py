#!/usr/bin/env python3
"""Copies the mesh files of the cached data packages into one folder, for the ignored survey
in crate/tests/io_game.rs (which reads files, not archives).

Walks the wheels (`wheels/*.whl`) and the unpacked Debian packages (`unpacked/*`) of the
`meshflow data` cache, opens zip archives (.zip, .pk3, .sh3f, .wz, .whl) down to four levels,
and writes every member or file with one of the extensions to OUT/<source>/<path>, an
archive's members under `<archive>/_in_/`.

    scripts/extract_meshes.py OUT [--cache ~/.cache/meshflow/data] [--ext dae,ase,iqm,md5mesh]
    MESHFLOW_GAME_DATA=OUT cargo test -p meshflow --test io_game -- --ignored --nocapture
"""
import argparse
import io
import os
import zipfile

ARCHIVES = ('.zip', '.pk3', '.sh3f', '.wz', '.whl')
DEFAULT_EXT = 'pmd,spm,md2,md3,pie,ac,dae,ase,iqm,md5mesh'


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('out')
    ap.add_argument('--cache', default=os.path.expanduser('~/.cache/meshflow/data'))
    ap.add_argument('--ext', default=DEFAULT_EXT, help='comma-separated, without dots')
    args = ap.parse_args()
    exts = tuple('.' + e.strip().lower() for e in args.ext.split(','))
    count = 0

    def save(rel, data):
        nonlocal count
        path = os.path.join(args.out, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, 'wb') as f:
            f.write(data)
        count += 1

    def walk_zip(z, prefix, depth):
        for info in z.infolist():
            low = info.filename.lower()
            if info.is_dir():
                continue
            if low.endswith(exts):
                save(f'{prefix}/_in_/{info.filename}', z.read(info))
            elif low.endswith(ARCHIVES) and depth < 4:
                try:
                    inner = zipfile.ZipFile(io.BytesIO(z.read(info)))
                except zipfile.BadZipFile:
                    print(f'not a zip: {prefix}/_in_/{info.filename}')
                    continue
                walk_zip(inner, f'{prefix}/_in_/{info.filename}', depth + 1)

    wheels = os.path.join(args.cache, 'wheels')
    for w in sorted(os.listdir(wheels)) if os.path.isdir(wheels) else []:
        if w.endswith('.whl'):
            walk_zip(zipfile.ZipFile(os.path.join(wheels, w)), f'wheels/{w}', 0)
    unpacked = os.path.join(args.cache, 'unpacked')
    for pkg in sorted(os.listdir(unpacked)) if os.path.isdir(unpacked) else []:
        base = os.path.join(unpacked, pkg)
        for d, _, files in os.walk(base):
            for name in sorted(files):
                full = os.path.join(d, name)
                rel = f'debs/{pkg}/{os.path.relpath(full, base)}'
                low = name.lower()
                if low.endswith(exts):
                    with open(full, 'rb') as f:
                        save(rel, f.read())
                elif low.endswith(ARCHIVES):
                    try:
                        walk_zip(zipfile.ZipFile(full), rel, 0)
                    except zipfile.BadZipFile:
                        print(f'not a zip: {rel}')
    print(f'{count} files in {args.out}')


if __name__ == '__main__':
    main()
