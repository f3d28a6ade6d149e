# %% [markdown]
# # openEMSS from Python: run, tabulate, compare
#
# A notebook in the "percent" format (cells start with `# %%`): open it in Jupyter with jupytext or
# VS Code, or run it as a script: `python examples/notebook_api.py [OUT_DIR]`. It flies the first
# 240 s of the Munich mission (brake release, take-off, climb) with two engines and compares them.
#
# `openemss.run` is the code behind `emss run`: same arguments (`stop_time`, `params`, `set`,
# `scenario`, `out`, `record`, `format`, ...), same results folder. It returns a `RunResult`:
# `r.df` (pandas, indexed by `time_s`, units in `r.df.attrs["units"]`), `r["component.variable"]`
# (NumPy), `r.summary` (summary.json of a mission run), `r.info` (run.json), `r.files`.

# %%
import sys
from pathlib import Path

import openemss

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("results") / "notebook"

# %% [markdown]
# ## Two runs: the shipped Larzac 04 and the reference study's engine model

# %%
runs = {
    "larzac04": openemss.run(stop_time=240.0, out=out / "larzac04"),
    "reference_study": openemss.run(stop_time=240.0, set={"engine.preset": "reference_study"},
                                    out=out / "reference_study"),
}
for name, r in runs.items():
    print(f"{name}: {r.status}, {r.rows} rows, {len(r.df.columns)} columns, t = {r['time_s'][-1]:.1f} s")

# %% [markdown]
# ## A table per run: pandas, with the units of every column

# %%
r = runs["larzac04"]
df = r.df
print(df[["engine.Fn_N", "engine.Wf_kg_s", "airframe.alt_m"]].describe().round(3))
print({c: df.attrs["units"][c] for c in ("engine.Fn_N", "engine.Wf_kg_s", "airframe.alt_m")})

# %% [markdown]
# ## Compare: fuel burned, maximum thrust and Tt4, the altitude reached

# %%
import pandas as pd  # noqa: E402

rows = []
for name, r in runs.items():
    d = r.df
    rows.append({"engine": name,
                 "fuel burned [kg]": d["engine.fuel_burned_kg"].iloc[-1] - d["engine.fuel_burned_kg"].iloc[0],
                 "max thrust [kN]": d["engine.Fn_N"].max() / 1e3,
                 "max Tt4 [K]": d["engine.Tt4_K"].max(),
                 "altitude at 240 s [m]": d["airframe.alt_m"].iloc[-1]})
table = pd.DataFrame(rows).set_index("engine")
print(table.round(2))

# %% [markdown]
# ## A figure from the tables (matplotlib through pandas)

# %%
import matplotlib  # noqa: E402

matplotlib.use("Agg")
ax = None
for name, r in runs.items():
    ax = (r.df["engine.Fn_N"] / 1e3).plot(ax=ax, label=name)
ax.set_ylabel("net thrust [kN]")
ax.legend()
ax.figure.savefig(out / "thrust_compare.png", dpi=100)
print(f"figure: {out / 'thrust_compare.png'}; each run's report: {runs['larzac04'].out / 'report.html'}")
