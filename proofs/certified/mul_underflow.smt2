; A product that lands below the normal range lies within one subnormal step of the two directed
; roundings, so round-to-nearest is within 2^-150 of the exact product (gradual underflow's eta).
(set-logic QF_FP)
(declare-const x (_ FloatingPoint 8 24))
(declare-const y (_ FloatingPoint 8 24))
(define-fun minnormal () (_ FloatingPoint 8 24) ((_ to_fp 8 24) RNE (/ 1.0 85070591730234615865843651857942052864.0)))
(define-fun step () (_ FloatingPoint 8 24) ((_ to_fp 8 24) RNE (/ 1.0 713623846352979940529142984724747568191373312.0)))
(assert (not (or (fp.isNaN x) (fp.isInfinite x) (fp.isNaN y) (fp.isInfinite y))))
(assert (fp.lt (fp.abs (fp.mul RNE x y)) minnormal))
(assert (fp.gt (fp.sub RNE (fp.mul RTP x y) (fp.mul RTN x y)) step))
(check-sat)
