; Hauser: a difference of two f32 values that lands below the normal range is exact
; (round-down and round-up agree), so a sum's absolute underflow error is 0 with gradual underflow.
(set-logic QF_FP)
(declare-const x (_ FloatingPoint 8 24))
(declare-const y (_ FloatingPoint 8 24))
(assert (not (or (fp.isNaN x) (fp.isInfinite x) (fp.isNaN y) (fp.isInfinite y))))
(assert (fp.isSubnormal (fp.sub RNE x y)))
(assert (not (fp.eq (fp.sub RTN x y) (fp.sub RTP x y))))
(check-sat)
