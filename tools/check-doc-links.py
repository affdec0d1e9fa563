#!/usr/bin/env python3
"""Checks the cross-references of README.md, docs/*.md and docs/notes/*.md:
- every inline relative link, [text](target): the file it names exists
  and, for a Markdown file, so does the #anchor (GitHub's heading anchors,
  and <a name=...>); links inside code spans and ``` fenced blocks are
  skipped, reference-style links are not checked;
- every section named in quotes after a Markdown file, as in
  (docs/firmware.md, "Parameters"): the file (from the page's folder, the
  source root or docs/) has a heading or a bold lead-in (**Name.**) that
  starts with or contains the quoted words.
Usage: check-doc-links.py SOURCE_DIR; prints each broken reference as
file:line and exits 1 if there is one."""
import re, os, sys, glob, unicodedata
root=sys.argv[1]
files=[os.path.join(root,'README.md')]+sorted(glob.glob(os.path.join(root,'docs/*.md')))+sorted(glob.glob(os.path.join(root,'docs/notes/*.md')))
def slug(h):
    h=h.strip().lower()
    h=re.sub(r'[^\w\- ]','',h)   # GitHub: drop punctuation except - and _ (keeps unicode letters)
    return h.replace(' ','-')
cache={}
def anchors(path):
    if path in cache: return cache[path]
    a=set(); counts={}
    infence=False
    for line in open(path,encoding='utf-8'):
        if line.lstrip().startswith('```'): infence=not infence; continue
        if infence: continue
        m=re.match(r'^(#{1,6})\s+(.*?)\s*#*\s*$',line)
        if m:
            t=re.sub(r'`','',m.group(2))
            t=re.sub(r'\[([^\]]*)\]\([^)]*\)',r'\1',t)
            sl=slug(t); n=counts.get(sl,0); counts[sl]=n+1
            a.add(sl if n==0 else f"{sl}-{n}")
        for m2 in re.finditer(r'<a (?:name|id)="([^"]+)"',line): a.add(m2.group(1))
    cache[path]=a; return a
bad=0; total=0
for f in files:
    infence=False
    for ln,line in enumerate(open(f,encoding='utf-8'),1):
        if line.lstrip().startswith('```'): infence=not infence; continue
        if infence: continue
        line2=re.sub(r'`[^`]*`','',line)
        for m in re.finditer(r'\]\(([^)\s]+)(?:\s+"[^"]*")?\)',line2):
            u=m.group(1)
            if re.match(r'^[a-z]+:',u) : continue
            total+=1
            path,_,frag=u.partition('#')
            tgt=os.path.normpath(os.path.join(os.path.dirname(f),path)) if path else f
            if not os.path.exists(tgt):
                print(f"{os.path.relpath(f,root)}:{ln}: missing file {u}"); bad+=1; continue
            if frag and tgt.endswith('.md') and frag not in anchors(tgt):
                print(f"{os.path.relpath(f,root)}:{ln}: missing anchor {u}"); bad+=1
def sections(path):
    out = []
    for line in open(path, encoding='utf-8'):
        m = re.match(r'^#{1,6}\s+(.*)', line) or re.match(r'^\*\*([^*]+)\*\*', line)
        if m: out.append(re.sub(r'[`*]', '', m.group(1)).strip().rstrip('.').lower())
    return out
quoted = 0
for f in files:
    for ln, line in enumerate(open(f, encoding='utf-8'), 1):
        for m in re.finditer(r'([\w./-]+\.md),?\s+"([^"]+)"', line):
            path, title = m.group(1), m.group(2).strip().rstrip('.').lower()
            where = [os.path.join(os.path.dirname(f), path), os.path.join(root, path), os.path.join(root, 'docs', path)]
            tgt = next((w for w in where if os.path.isfile(w)), None)
            quoted += 1
            if not tgt:
                print(f"{os.path.relpath(f,root)}:{ln}: missing file {path} (section \"{m.group(2)}\")"); bad += 1
            elif not any(h.startswith(title) or title in h for h in sections(tgt)):
                print(f"{os.path.relpath(f,root)}:{ln}: no section \"{m.group(2)}\" in {path}"); bad += 1
print(f"{total} relative links, {quoted} quoted sections, {bad} broken")
sys.exit(1 if bad else 0)
