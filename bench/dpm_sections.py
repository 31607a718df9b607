#!/usr/bin/python3
"""Where a .dpm's bytes go, by chunk kind and by SPLT section (docs/FORMAT.md "SPLT payload").

usage: dpm_sections.py FILE.dpm...

Prints per file: the total, the bytes of each chunk tag (headers included), the SPLT sections
summed over the chunks (records, attributes, positions of every step), and the positions in
bytes per vertex per step (the split vertices' sections only; BASE holds the base vertices').
Reads chunk headers only; checks nothing a reader checks.
"""
import struct
import sys
from collections import Counter

HEADER = 24  # tag, flags, stored size, raw size, CRC-32, 0


def sections(path):
    data = open(path, 'rb').read()
    tags, split = Counter(), Counter()
    vertices = steps = 0
    at = 12  # magic, version
    while at + HEADER <= len(data):
        tag = data[at:at + 4].decode('ascii', 'replace')
        stored = struct.unpack_from('<I', data, at + 8)[0]
        payload = data[at + HEADER:at + HEADER + stored]
        tags[tag] += HEADER + stored
        if tag == 'HEAD':
            vertices = struct.unpack_from('<I', payload, 0)[0]
            steps = struct.unpack_from('<I', payload, 20)[0]
        elif tag == 'SPLT':
            count = struct.unpack_from('<I', payload, 8)[0]
            sizes = struct.unpack_from('<%dI' % count, payload, 12)
            split['records'] += sizes[0]
            split['attributes'] += sizes[1]
            split['positions'] += sum(sizes[2:])
        at += HEADER + stored
    return len(data), tags, split, vertices, steps


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for path in sys.argv[1:]:
        total, tags, split, vertices, steps = sections(path)
        print('%s: %d bytes, %d vertices, %d steps' % (path, total, vertices, steps))
        print('  chunks    ' + ', '.join('%s %d' % kv for kv in sorted(tags.items())))
        print('  SPLT      records %d, attributes %d, positions %d' %
              (split['records'], split['attributes'], split['positions']))
        if vertices and steps:
            print('  positions %.3f B per vertex per step' %
                  (split['positions'] / (vertices * steps)))


if __name__ == '__main__':
    main()
