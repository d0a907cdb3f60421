; The gate: if each of x, y is zero or at least 2^-102 in magnitude, x - y is zero or normal
; (never flushed). Also: it is exact or has only relative error then (normal result).
(set-logic QF_FP)
(declare-const x (_ FloatingPoint 8 24))
(declare-const y (_ FloatingPoint 8 24))
(define-fun tiny () (_ FloatingPoint 8 24) ((_ to_fp 8 24) RNE (/ 1.0 5070602400912917605986812821504.0)))
(assert (not (or (fp.isNaN x) (fp.isInfinite x) (fp.isNaN y) (fp.isInfinite y))))
(assert (or (fp.isZero x) (fp.geq (fp.abs x) tiny)))
(assert (or (fp.isZero y) (fp.geq (fp.abs y) tiny)))
(assert (fp.isSubnormal (fp.sub RNE x y)))
(check-sat)
