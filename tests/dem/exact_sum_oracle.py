"""Oracle for exact_sum_test: each input line holds hexadecimal doubles (C's %a), the terms of
one sum; prints float.hex of their exact rational sum rounded to the nearest double, ties to
even (Python's float(Fraction) rounds correctly), "inf"/"-inf" beyond the range."""
import sys
from fractions import Fraction

for line in sys.stdin:
    terms = [float.fromhex(t) for t in line.split()]
    exact = sum((Fraction(t) for t in terms), Fraction(0))
    try:
        print(float(exact).hex())
    except OverflowError:
        print("inf" if exact > 0 else "-inf")
