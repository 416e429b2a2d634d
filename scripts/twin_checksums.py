#!/usr/bin/env python3
# Checksums of every file of a twin output folder (OUT/.cache left out), with the timing fields
# removed as tests/test_cli.cpp withoutTimings does: materials/*.json fit.seconds, metrics.json
# stages / total_seconds / peak_memory_mib; report.html is listed but not compared (it shows the
# timings). Two runs give the same lines when their outputs are byte-identical:
#   python3 scripts/twin_checksums.py OUT_A > a.txt; python3 scripts/twin_checksums.py OUT_B | diff a.txt -
import hashlib, json, os, sys
root = sys.argv[1]
for dp, dn, fn in sorted(os.walk(root)):
    dn.sort()
    rel = os.path.relpath(dp, root)
    if rel.split(os.sep)[0] == '.cache': continue
    for f in sorted(fn):
        p = os.path.join(dp, f); r = os.path.normpath(os.path.join(rel, f))
        data = open(p, 'rb').read()
        if f.endswith('.json'):
            j = json.loads(data)
            if r.startswith('materials/') and isinstance(j.get('fit'), dict): j['fit'].pop('seconds', None)
            if r == 'metrics.json':
                for k in ('stages', 'total_seconds', 'peak_memory_mib'): j.pop(k, None)
            data = json.dumps(j, sort_keys=True).encode()
        if r == 'report.html': r += ' (timings inside; not compared)'; data = b''
        print(hashlib.md5(data).hexdigest(), r)
