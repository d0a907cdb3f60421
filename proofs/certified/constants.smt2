; certified's constants (src/methods/certified.rs, Bound) against the conditions of the derivation
; in src/methods/certified.md, in exact rational arithmetic. Each block asserts that a condition
; fails; `unsat` means every condition holds. tests/proofs.rs checks that the constants here are
; the ones in the code.
(set-logic QF_NRA)

; GRADUAL (cpu, cpu-fma): round to nearest, gradual underflow
(push 1)
(define-fun u () Real (/ 1.0 16777216.0))
(define-fun eta_m () Real (/ 1.0 1427247692705959881058285969449495136382746624.0))
(define-fun eta_a () Real 0.0)
; bound constants: a = 2^-21, mu = 2^-126, c = 2^-126
(define-fun A () Real (/ 1.0 2097152.0))
(define-fun MU () Real (/ 1.0 85070591730234615865843651857942052864.0))
(define-fun C () Real (/ 1.0 85070591730234615865843651857942052864.0))
(define-fun g2 () Real (/ (* 2.0 u) (- 1.0 (* 2.0 u))))
(define-fun g3 () Real (/ (* 3.0 u) (- 1.0 (* 3.0 u))))
(define-fun g4 () Real (/ (* 4.0 u) (- 1.0 (* 4.0 u))))
(define-fun g7 () Real (/ (* 7.0 u) (- 1.0 (* 7.0 u))))
(define-fun v () Real (- 1.0 u))
; G = g7 / ((1-u)^5 (1-g3)); tau = 2(1+u) eta_m + eta_a; C0 = 3(1+g2) eta_m + (2+u) eta_a
(define-fun G () Real (/ g7 (* v v v v v (- 1.0 g3))))
(define-fun tau () Real (+ (* 2.0 (+ 1.0 u) eta_m) eta_a))
(define-fun C0 () Real (+ (* 3.0 (+ 1.0 g2) eta_m) (* (+ 2.0 u) eta_a)))
(assert (not (and
  ; (R) the relative part: (1-u) a >= G
  (>= (* v A) G)
  ; (M) mu carries w's absolute error: mu >= tau (1 + (1+g4)(1-g3)/g7)
  (>= MU (* tau (+ 1.0 (/ (* (+ 1.0 g4) (- 1.0 g3)) g7))))
  ; (C) the absolute part: (1-u)(c - eta_m) >= G (3 eta_m + 2 eta_a) + C0
  (>= (* v (- C eta_m)) (+ (* G (+ (* 3.0 eta_m) (* 2.0 eta_a))) C0))
  ; mu and c are normal (a flushing processor keeps them)
  (>= MU (/ 1.0 85070591730234615865843651857942052864.0))
  (>= C (/ 1.0 85070591730234615865843651857942052864.0)))))
(check-sat)
(pop 1)

; FLUSHING (cpu-ftz): round to nearest, subnormals flushed, inputs gated
(push 1)
(define-fun u () Real (/ 1.0 16777216.0))
(define-fun eta_m () Real (/ 1.0 85070591730234615865843651857942052864.0))
(define-fun eta_a () Real (/ 1.0 85070591730234615865843651857942052864.0))
; bound constants: a = 2^-21, mu = 2^-102, c = 2^-122
(define-fun A () Real (/ 1.0 2097152.0))
(define-fun MU () Real (/ 1.0 5070602400912917605986812821504.0))
(define-fun C () Real (/ 1.0 5316911983139663491615228241121378304.0))
(define-fun g2 () Real (/ (* 2.0 u) (- 1.0 (* 2.0 u))))
(define-fun g3 () Real (/ (* 3.0 u) (- 1.0 (* 3.0 u))))
(define-fun g4 () Real (/ (* 4.0 u) (- 1.0 (* 4.0 u))))
(define-fun g7 () Real (/ (* 7.0 u) (- 1.0 (* 7.0 u))))
(define-fun v () Real (- 1.0 u))
; G = g7 / ((1-u)^5 (1-g3)); tau = 2(1+u) eta_m + eta_a; C0 = 3(1+g2) eta_m + (2+u) eta_a
(define-fun G () Real (/ g7 (* v v v v v (- 1.0 g3))))
(define-fun tau () Real (+ (* 2.0 (+ 1.0 u) eta_m) eta_a))
(define-fun C0 () Real (+ (* 3.0 (+ 1.0 g2) eta_m) (* (+ 2.0 u) eta_a)))
(assert (not (and
  ; (R) the relative part: (1-u) a >= G
  (>= (* v A) G)
  ; (M) mu carries w's absolute error: mu >= tau (1 + (1+g4)(1-g3)/g7)
  (>= MU (* tau (+ 1.0 (/ (* (+ 1.0 g4) (- 1.0 g3)) g7))))
  ; (C) the absolute part: (1-u)(c - eta_m) >= G (3 eta_m + 2 eta_a) + C0
  (>= (* v (- C eta_m)) (+ (* G (+ (* 3.0 eta_m) (* 2.0 eta_a))) C0))
  ; mu and c are normal (a flushing processor keeps them)
  (>= MU (/ 1.0 85070591730234615865843651857942052864.0))
  (>= C (/ 1.0 85070591730234615865843651857942052864.0)))))
(check-sat)
(pop 1)

; GPU (certified.wgsl): any rounding within an ulp, flushed or not, inputs gated
(push 1)
(define-fun u () Real (/ 1.0 8388608.0))
(define-fun eta_m () Real (/ 1.0 85070591730234615865843651857942052864.0))
(define-fun eta_a () Real (/ 1.0 85070591730234615865843651857942052864.0))
; bound constants: a = 2^-20, mu = 2^-102, c = 2^-122
(define-fun A () Real (/ 1.0 1048576.0))
(define-fun MU () Real (/ 1.0 5070602400912917605986812821504.0))
(define-fun C () Real (/ 1.0 5316911983139663491615228241121378304.0))
(define-fun g2 () Real (/ (* 2.0 u) (- 1.0 (* 2.0 u))))
(define-fun g3 () Real (/ (* 3.0 u) (- 1.0 (* 3.0 u))))
(define-fun g4 () Real (/ (* 4.0 u) (- 1.0 (* 4.0 u))))
(define-fun g7 () Real (/ (* 7.0 u) (- 1.0 (* 7.0 u))))
(define-fun v () Real (- 1.0 u))
; G = g7 / ((1-u)^5 (1-g3)); tau = 2(1+u) eta_m + eta_a; C0 = 3(1+g2) eta_m + (2+u) eta_a
(define-fun G () Real (/ g7 (* v v v v v (- 1.0 g3))))
(define-fun tau () Real (+ (* 2.0 (+ 1.0 u) eta_m) eta_a))
(define-fun C0 () Real (+ (* 3.0 (+ 1.0 g2) eta_m) (* (+ 2.0 u) eta_a)))
(assert (not (and
  ; (R) the relative part: (1-u) a >= G
  (>= (* v A) G)
  ; (M) mu carries w's absolute error: mu >= tau (1 + (1+g4)(1-g3)/g7)
  (>= MU (* tau (+ 1.0 (/ (* (+ 1.0 g4) (- 1.0 g3)) g7))))
  ; (C) the absolute part: (1-u)(c - eta_m) >= G (3 eta_m + 2 eta_a) + C0
  (>= (* v (- C eta_m)) (+ (* G (+ (* 3.0 eta_m) (* 2.0 eta_a))) C0))
  ; mu and c are normal (a flushing processor keeps them)
  (>= MU (/ 1.0 85070591730234615865843651857942052864.0))
  (>= C (/ 1.0 85070591730234615865843651857942052864.0)))))
(check-sat)
(pop 1)
