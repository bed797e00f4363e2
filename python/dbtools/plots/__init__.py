"""The figures, one module per experiment named after it (applications, frames, solvers, table_2_1; history: the
tracking suite's trend view), each drawing PNGs from the CSVs only, into RESULTS/figures; render_meshes draws the
frames study's meshes (and holds the mesh drawing applications uses), styles is the one colour + marker table.
Every module's plot(results, out) is what the report step calls (python3 -m dbtools.report --only NAME redraws one
experiment's figures and rewrites its reports); those with options of their own (render_meshes and applications:
--cases, history: --machine) also run alone: python3 -m dbtools.plots.NAME --help."""
