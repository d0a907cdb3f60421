; Overflow and NaN reach the permanent: with round to nearest, |fl(p1 - p2)| <= fl(|p1| + |p2|), so
; m >= |w| as computed, and an infinite side product has an infinite permanent (the bound fails).
(set-logic QF_FP)
(declare-const x (_ FloatingPoint 8 24))
(declare-const y (_ FloatingPoint 8 24))
(assert (not (or (fp.isNaN x) (fp.isNaN y))))
(assert (not (fp.isNaN (fp.sub RNE x y))))
(assert (fp.gt (fp.abs (fp.sub RNE x y)) (fp.add RNE (fp.abs x) (fp.abs y))))
(check-sat)
