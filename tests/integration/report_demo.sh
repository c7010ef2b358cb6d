# The report of the simulated campaign: every output written, groups and comparisons as expected,
# numbers recomputed with other settings on a re-run, the HTML page opened in a real headless browser
# (no console message, every chart present and non-empty, a screenshot kept beside the executable in
# test-artifacts/), and the pgfplots figures compiled with pdflatex. The browser and TeX parts are
# skipped, saying so, when chromium or pdflatex with pgfplots is not installed.
source "$(dirname "$0")/lib.bash"
ARTIFACTS=$(dirname "$M2MLAT")/test-artifacts
mkdir -p "$ARTIFACTS"
skipped=0

"$M2MLAT" demo --store c.db > /dev/null
"$M2MLAT" report c.db --out out > report.txt
for f in report.html report.md report.json scenarios.csv comparisons.csv pgfplots/figures.tex pgfplots/box.tex \
         pgfplots/box.dat pgfplots/ecdf.tex pgfplots/histogram.tex pgfplots/timeseries-static_wifi.tex \
         pgfplots/clock-static_5g.tex; do
  [ -s "out/$f" ] || fail "out/$f missing or empty"
done
grep -q "static_5g vs static_wifi: IQR" report.txt || fail "no comparison sentence in the terminal report"
$PY - out/report.json <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
assert doc["format"] == "m2mlat-report/1"
assert doc["generated_by"]["command"].startswith("m2mlat report c.db"), doc["generated_by"]
assert doc["groups"] == ["static", "dynamic"], doc["groups"]
names = [s["scenario"] for s in doc["scenarios"]]
assert names == ["static_wifi", "static_5g", "dynamic_co_referenced", "dynamic_autonomous"], names
pairs = [(c["subject"], c["baseline"]) for c in doc["comparisons"]]
assert pairs == [("static_5g", "static_wifi"), ("dynamic_autonomous", "dynamic_co_referenced")], pairs
for s in doc["scenarios"]:
    u = s["uncertainty"]
    assert u["pairs_with_bound"] == s["pairing"]["pairs"] and u["median_ms"] > 0, u   # the demo records clock samples
    assert len(s["clocks"]) == 2, s["clocks"]
PY

# Other settings on a re-run: no groups (so all 6 comparisons), another threshold, another window.
"$M2MLAT" report c.db --no-groups --threshold 900ms --max-latency 2s --bootstrap 300 --seed 5 --print json > regrouped.json
$PY - regrouped.json <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
assert doc["groups"] == [] and len(doc["comparisons"]) == 6
assert [a["threshold_ns"] for a in doc["scenarios"][0]["latency"]["above"]] == [900000000]
b = doc["comparisons"][0]["bootstrap"]
assert (b["level"], b["resamples"], b["seed"]) == (0.95, 300, 5), b
assert b["subject_resampled"] in ("pairs", "manoeuvres") or b["subject_resampled"].startswith("blocks of "), b
PY
"$M2MLAT" report c.db --group fast=static_5g,dynamic_autonomous --compare static_wifi:dynamic_autonomous --print csv-comparisons > cmp.csv
[ "$(wc -l < cmp.csv)" = 2 ] && grep -q '^static_wifi,dynamic_autonomous,' cmp.csv || fail "explicit --compare: $(cat cmp.csv)"
# The baseline is the first scenario given, or --baseline: every other scenario of its group against it.
"$M2MLAT" report c.db --scenario static_5g --scenario static_wifi --print json > first.json
"$M2MLAT" report c.db --no-groups --baseline dynamic_autonomous --print json > based.json
$PY - first.json based.json <<'PY'
import json, sys
first, based = (json.load(open(p)) for p in sys.argv[1:3])
assert [(c["subject"], c["baseline"]) for c in first["comparisons"]] == [("static_wifi", "static_5g")], first["comparisons"]
pairs = [(c["subject"], c["baseline"]) for c in based["comparisons"]]
assert sorted(pairs) == sorted((s, "dynamic_autonomous") for s in ("static_wifi", "static_5g", "dynamic_co_referenced")), pairs
PY
expect_exit 2 "$M2MLAT" report c.db --baseline static_5gg
grep -q "no scenario 'static_5gg' (did you mean 'static_5g'?)" err.txt || fail "unknown baseline: $(cat err.txt)"
expect_exit 2 "$M2MLAT" report c.db --compare nope:static_5g
grep -q "no scenario 'nope'" err.txt || fail "unknown scenario: $(cat err.txt)"
expect_exit 2 "$M2MLAT" report c.db --group nonsense

# The HTML page in a real browser.
if command -v chromium > /dev/null; then
  chrome=(chromium --headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking
          --disable-component-update --disable-sync --enable-logging=stderr --v=0)
  page="file://$PWD/out/report.html"
  timeout 120 "${chrome[@]}" --user-data-dir="$PWD/chrome-1" --dump-dom "$page" > dom.html 2> chrome.err
  timeout 120 "${chrome[@]}" --user-data-dir="$PWD/chrome-2" --window-size=1000,4000 \
    --screenshot="$ARTIFACTS/report_demo.png" "$page" > /dev/null 2>> chrome.err
  [ -s "$ARTIFACTS/report_demo.png" ] || fail "no screenshot"
  if grep -E "CONSOLE|Uncaught|Failed to load resource" chrome.err; then fail "console messages from the report page"; fi
  # The checker itself must see a broken page as broken.
  printf '<!DOCTYPE html><p>x</p><script>undefinedFunction();</script>' > broken.html
  timeout 120 "${chrome[@]}" --user-data-dir="$PWD/chrome-3" --dump-dom "file://$PWD/broken.html" > /dev/null 2> broken.err
  grep -q "CONSOLE" broken.err || fail "the console check did not see a script error"
  # Layout, at a desktop and a phone width: a copy of the page with a probe script at its end (the page
  # itself has none) reports every table or chart wider than the page and any two x-axis labels of one
  # chart that overlap.
  probe='<script>(function(){const w=document.documentElement.clientWidth,bad=[];
for(const t of document.querySelectorAll("table"))if(t.getBoundingClientRect().right>w+1||t.scrollWidth>t.clientWidth+1)bad.push("table "+t.dataset.table);
for(const s of document.querySelectorAll("svg")){if(s.getBoundingClientRect().right>w+1)bad.push("wide "+s.dataset.chart);
const r=[...s.querySelectorAll("text.tick[text-anchor=middle]")].map(t=>t.getBoundingClientRect());
for(let i=0;i<r.length;i++)for(let j=i+1;j<r.length;j++){const a=r[i],b=r[j];
if(a.left<b.right-0.5&&b.left<a.right-0.5&&a.top<b.bottom-0.5&&b.top<a.bottom-0.5)bad.push("labels overlap in "+s.dataset.chart);}}
document.body.setAttribute("data-probe",JSON.stringify({width:w,bad:bad}));})();</script>'
  sed "s#</body>#$(printf '%s' "$probe" | tr '\n' ' ' | sed 's/[&#]/\\&/g')</body>#" out/report.html > probe.html
  for size in 1000,3000 390,3000; do
    timeout 120 "${chrome[@]}" --user-data-dir="$PWD/chrome-p$size" --window-size=$size --dump-dom \
      "file://$PWD/probe.html" > probe-dom.html 2>> chrome.err
    $PY - probe-dom.html "$size" <<'PY'
import json, re, sys
m = re.search(r'data-probe="([^"]*)"', open(sys.argv[1]).read())
assert m, "the layout probe did not run"
probe = json.loads(m.group(1).replace("&quot;", '"'))
assert not probe["bad"], (sys.argv[2], probe)
print("layout at", sys.argv[2], "ok: page width", probe["width"])
PY
  done
  $PY - dom.html <<'PY'
import sys
from html.parser import HTMLParser
want = ["forest", "box", "ecdf", "histogram", "timeseries-0", "timeseries-1", "timeseries-2", "timeseries-3",
        "clock-0", "clock-1", "clock-2", "clock-3", "budget"]
class Charts(HTMLParser):
    def __init__(self):
        super().__init__(); self.marks = {}; self.chart = None; self.depth = 0
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "svg" and "data-chart" in a:
            self.chart = a["data-chart"]; self.marks[self.chart] = 0
        elif self.chart and tag in ("rect", "circle", "polyline", "polygon", "line") and "class" in a \
                and a["class"] not in ("grid", "frame"):
            self.marks[self.chart] += 1
    def handle_endtag(self, tag):
        if tag == "svg": self.chart = None
p = Charts(); p.feed(open(sys.argv[1]).read())
missing = [c for c in want if c not in p.marks]
empty = [c for c in want if p.marks.get(c, 0) < 3]
assert not missing and not empty, ("missing", missing, "empty", empty, p.marks)
print("charts:", p.marks)
PY
else
  echo "skipped: chromium is not installed (apt-get install chromium): the HTML was not opened in a browser"
  skipped=$((skipped + 1))
fi

# The pgfplots figures compiled.
if command -v pdflatex > /dev/null && kpsewhich pgfplots.sty > /dev/null 2>&1; then
  (cd out/pgfplots && timeout 300 pdflatex -interaction=nonstopmode -halt-on-error figures.tex > latex.out 2>&1) ||
    { tail -30 out/pgfplots/latex.out >&2; fail "pdflatex failed on the pgfplots figures"; }
  [ -s out/pgfplots/figures.pdf ] || fail "no figures.pdf"
  cp out/pgfplots/figures.pdf "$ARTIFACTS/report_demo_figures.pdf"
else
  echo "skipped: pdflatex with pgfplots is not installed (apt-get install texlive-latex-base texlive-pictures)"
  skipped=$((skipped + 1))
fi
echo "1 passed, 0 failed, $skipped skipped"

# `demo --report DIR`: the same report straight from the demo (what `make demo` ends with): the
# scenarios' figures and the full loop's, the same comparisons as `report` of the demo's store.
"$M2MLAT" demo --report direct --scenario static_wifi --scenario static_5g --scenario full_loop > demo.txt
grep -q "report: direct/report.html" demo.txt || fail "demo --report: $(tail -3 demo.txt)"
for f in report.html report.md report.json scenarios.csv comparisons.csv full_loop.csv pgfplots/figures.tex; do
  [ -s "direct/$f" ] || fail "direct/$f missing or empty"
done
$PY - direct/report.json <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
names = [s["scenario"] for s in r["scenarios"]]
assert names == ["static_wifi", "static_5g"], names
assert any(c["subject"] == "static_5g" and c["baseline"] == "static_wifi" for c in r["comparisons"]), r["comparisons"]
assert "demo" in r["generated_by"]["command"], r["generated_by"]
PY
