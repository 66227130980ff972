#!/usr/bin/env bash
# Every relative link and image of README.md, BENCHMARKS.md and docs/*.md
# resolves: the file exists, and a #fragment names a heading of it (GitHub's
# anchors). Prints each broken link as FILE:LINE: target; exit status 1 if any.
#   bash scripts/doc-links.sh
set -euo pipefail
cd "$(dirname "$0")/.."
python3 - README.md BENCHMARKS.md docs/*.md <<'EOF'
import os, re, sys

def anchors(path):
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to -."""
    seen, out = {}, set()
    fence = False
    for line in open(path, encoding="utf-8"):
        if line.lstrip().startswith("```"):
            fence = not fence
        if fence or not line.startswith("#"):
            continue
        text = line.lstrip("#").strip()
        text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
        slug = re.sub(r"[^\w\- ]", "", text.lower().replace("`", "")).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        out.add(slug if n == 0 else f"{slug}-{n}")
    return out

bad = 0
link = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
for md in sys.argv[1:]:
    if not os.path.exists(md):
        continue
    fence = False
    for no, line in enumerate(open(md, encoding="utf-8"), 1):
        if line.lstrip().startswith("```"):
            fence = not fence
        if fence:
            continue
        for target in link.findall(line):
            if re.match(r"[a-z]+:", target):
                continue
            path, _, frag = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(md), path)) if path else md
            if not os.path.exists(dest):
                print(f"{md}:{no}: {target} (no such file)")
                bad += 1
            elif frag and dest.endswith(".md") and frag not in anchors(dest):
                print(f"{md}:{no}: {target} (no such heading)")
                bad += 1
print(f"{bad} broken link(s)" if bad else "every relative link resolves")
sys.exit(1 if bad else 0)
EOF
