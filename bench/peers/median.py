# SPDX-License-Identifier: Apache-2.0
"""median.py OUT ROUND.json...: copy to OUT the round whose process() p50
(metering off) is the median of the rounds', with "rounds" added: how many
ran and that this is their median. One engine's rounds of bench/peers
(run.sh), run alternating with the other engines'."""
import json
import sys


def p50(doc: dict) -> float:
    for fig in doc["figures"]:
        if fig["name"] == "process, metering off":
            return fig["p50"]
    raise SystemExit(f"median.py: no 'process, metering off' figure in {doc.get('engine')}")


def main() -> None:
    out, paths = sys.argv[1], sys.argv[2:]
    if not paths:
        raise SystemExit("median.py: no rounds")
    docs = [json.load(open(p, encoding="utf-8")) for p in paths]
    docs.sort(key=p50)
    pick = docs[(len(docs) - 1) // 2]
    pick["rounds"] = {"runs": len(docs), "median_by": "process, metering off (p50)",
                      "p50s": [p50(d) for d in docs]}
    with open(out, "w", encoding="utf-8") as f:
        json.dump(pick, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
