"""readme_example.py README EXAMPLE: the README's code block after the line
<!--example:examples/NAME--> must be the example file, line for line, so the README never shows
code that CI does not build and run."""
import sys
from pathlib import Path

readme, example = Path(sys.argv[1]), Path(sys.argv[2])
marker = f"<!--example:examples/{example.name}-->"
lines = readme.read_text().splitlines()
if marker not in lines:
    sys.exit(f"{readme}: no line {marker}")
start = lines.index(marker) + 1
if lines[start] != "```cpp":
    sys.exit(f"{readme}: the line after {marker} must open a ```cpp block")
end = lines.index("```", start + 1)
shown, actual = lines[start + 1 : end], example.read_text().splitlines()
if shown != actual:
    for k, (a, b) in enumerate(zip(shown, actual)):
        if a != b:
            sys.exit(f"README line {start + 2 + k} differs from {example.name} line {k + 1}:\n"
                     f"  README:  {a}\n  example: {b}")
    sys.exit(f"README shows {len(shown)} lines, {example.name} has {len(actual)}")
print(f"README shows {example.name} as it is ({len(actual)} lines)")
