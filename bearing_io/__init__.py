"""bearing_io: the file writing, progress reports and report pages both packages need.

Neither package's signal or solver code: atomic writes of results (:mod:`bearing_io.files`:
write to a temporary name, then rename, so a crash never leaves a half-written file),
progress on long work (:mod:`bearing_io.progress`: a bar on a terminal, timed lines in a
log) and the look of the HTML reports (:mod:`bearing_io.report_html`: one self-contained
page, CSS inline, figures as data URIs). Standard library and numpy only, so
``diagnostics`` stays usable without the simulator and ``taichi_bearing`` without the
diagnostics' application code.
"""
