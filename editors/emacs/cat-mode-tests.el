;;; cat-mode-tests.el --- ERT tests for cat-mode  -*- lexical-binding: t; -*-

;; SPDX-License-Identifier: MIT

;;; Commentary:

;; Run from the repository root:
;;
;;     emacs --batch -Q -L editors/emacs -l editors/emacs/cat-mode-tests.el \
;;           -f ert-run-tests-batch-and-exit
;;
;; With CAT_KEYWORDS_JSON naming a JSON file {"category": ["word", ...], ...} (the pytest
;; wrapper tests/editors/test_emacs.py writes one from catgrammar.symbols.all_keywords()),
;; `cat-mode-test-every-keyword' also checks every word of the language.

;;; Code:

(require 'ert)
(require 'json)
(require 'imenu)
(require 'cat-mode)

(defconst cat-mode-test-sample
  "; detection domain -- TODO: more morphisms
(define (domain detection)
  (:requirements :numeric :sets :free-parameters :views :holes :recomposition)
  (:sorts module topic class - symbol  level - (enum low high))
  (:constants
    camera - module
    image-raw - topic
    person - class
    and-gate not-ready total-churn-x x-or camera2 realistic - class)
  (:resources
    (ram real :group compute :unit GB :bounds (0 *))
    (mounted (set module) :group hardware)
    (budget real :group external :bounds (-1.5E+2 *))
    (detects (set class) :group info)
    (armed bool :group safety)
    (topics (set topic) :group info :doc \"published \\\"ROS\\\" topics; not a comment\"))
  (:morphism camera-driver
    :kind software :churn 2 :uses 1
    :cost (+ 0.5 (* 2 .25) 1e-3 (- ram-req 0.25))
    :parameters ((out topic) (ram-req real :bounds (0.5 4) :fixed))
    :precondition (and (>= ram ram-req) (not (member out topics)))
    :effect (and (decrease ram ram-req) (add topics out)))
  (:morphism person-detector
    :kind software :churn 1
    :parameters ((c class))
    :precondition (and (member image-raw topics) (member camera mounted) (>= budget 0))
    :effect (and (add detects c) (assign armed true)))
  (:hole mu :view software :max-effects 2)
  (:view software :drop (mounted budget)))

(define (problem p1)
  (:domain detection)
  (:objects fire-extinguisher - class)
  (:init (= ram 64) (= mounted {camera}) (= budget 100) (= topics {}) (= detects {})
         (= armed false))
  (:goal (member person detects))
  (:horizon 8)
  (:soft (>= ram 16) :weight 5)
  (:metric lex (minimize (total-churn)) (maximize ram))
  (:deployed camera-driver)
  (:view software))
"
  "A .cat text with every kind of token, indented the way `cat-mode' indents.
The same text as editors/vim/test/sample.cat; it passes `catc check'.")

(defmacro cat-mode-test--with-buffer (text &rest body)
  "Run BODY in a `cat-mode' buffer holding TEXT, fontified, point at the start."
  (declare (indent 1) (debug t))
  `(with-temp-buffer
     (insert ,text)
     (cat-mode)
     (font-lock-ensure)
     (goto-char (point-min))
     ,@body))

(defun cat-mode-test--faces-at (pos)
  "The faces at POS, as a list."
  (let ((face (get-text-property pos 'face)))
    (if (listp face) face (list face))))

(defun cat-mode-test--check (context target face)
  "Check that every character of TARGET has FACE (nil: no face).
TARGET is looked up inside the first occurrence of CONTEXT in the
buffer.  Return nil when it does, else a description of the mismatch."
  (save-excursion
    (goto-char (point-min))
    (if (not (search-forward context nil t))
        (format "no %S in the buffer" context)
      (let* ((offset (string-match-p (regexp-quote target) context))
             (start (+ (match-beginning 0) (or offset 0)))
             (problem nil))
        (if (null offset)
            (format "%S is not inside %S" target context)
          (dotimes (i (length target))
            (let ((faces (cat-mode-test--faces-at (+ start i))))
              (unless (or problem
                          (if face (memq face faces) (null faces)))
                (setq problem (format "%S in %S (char %d): expected %S, got %S"
                                      target context i face faces)))))
          problem)))))

(defmacro cat-mode-test--expect-faces (&rest checks)
  "Check each (CONTEXT TARGET FACE) of CHECKS in the current buffer.
All failures are reported together."
  `(let ((failures (delq nil (mapcar (lambda (check) (apply #'cat-mode-test--check check))
                                     ',checks))))
     (should (equal failures nil))))

(ert-deftest cat-mode-test-auto-mode ()
  "Files named *.cat open in `cat-mode'."
  (should (eq (assoc-default "/tmp/detection.cat" auto-mode-alist #'string-match-p) 'cat-mode))
  (should-not (eq (assoc-default "/tmp/detection.cats" auto-mode-alist #'string-match-p) 'cat-mode)))

(ert-deftest cat-mode-test-faces ()
  "Each kind of token gets its face at sample positions."
  (cat-mode-test--with-buffer cat-mode-test-sample
    (cat-mode-test--expect-faces
     ("; detection domain -- TODO" ";" font-lock-comment-delimiter-face)
     ("; detection domain -- TODO" "detection domain -- TODO" font-lock-comment-face)
     ("(define (domain detection)" "define" cat-structure-face)
     ("(define (domain detection)" "domain" cat-structure-face)
     ("(define (domain detection)" "detection" nil)
     ("(:requirements :numeric" ":requirements" cat-section-face)
     (":numeric :sets :free-parameters :views" ":numeric" cat-requirement-face)
     (":numeric :sets :free-parameters :views" ":free-parameters" cat-requirement-face)
     (":free-parameters :views :holes :recomposition)" ":recomposition" cat-requirement-face)
     ("(:sorts module topic class - symbol" ":sorts" cat-section-face)
     ("(:sorts module topic class - symbol" "topic class" nil)
     ("(:sorts module topic class - symbol" "-" cat-symbol-operator-face)
     ("(:sorts module topic class - symbol" "symbol" cat-type-face)
     ("(enum low high)" "enum" cat-type-face)
     ("(enum low high)" "low high" nil)
     ("image-raw - topic" "image-raw" nil)
     ("(ram real :group compute" "real" cat-type-face)
     ("(ram real :group compute" ":group" cat-option-face)
     ("(ram real :group compute" "compute" nil)
     (":bounds (0 *)" ":bounds" cat-option-face)
     (":bounds (0 *)" "0" cat-number-face)
     (":bounds (0 *)" "*" cat-symbol-operator-face)
     ("(topics (set topic)" "set" cat-type-face)
     ("\"published \\\"ROS\\\" topics; not a comment\"" "; not a comment" font-lock-string-face)
     ("(:morphism camera-driver" ":morphism" cat-section-face)
     ("(:morphism camera-driver" "camera-driver" nil)
     (":kind software :churn 2 :uses 1" ":kind" cat-option-face)
     (":kind software :churn 2 :uses 1" "software" cat-kind-face)
     (":kind software :churn 2 :uses 1" ":uses" cat-option-face)
     (":kind software :churn 2 :uses 1" "2" cat-number-face)
     (":cost (+ 0.5" "+" cat-symbol-operator-face)
     (":cost (+ 0.5" "0.5" cat-number-face)
     ("(* 2 .25)" ".25" cat-number-face)
     (" 1e-3 " "1e-3" cat-number-face)
     ("(-1.5E+2 *)" "-1.5E+2" cat-number-face)
     ("(- ram-req 0.25)" "-" cat-symbol-operator-face)
     ("(- ram-req 0.25)" "ram-req" nil)
     ("(- ram-req 0.25)" "0.25" cat-number-face)
     ("(ram-req real :bounds (0.5 4) :fixed)" "ram-req" nil)
     ("(ram-req real :bounds (0.5 4) :fixed)" ":fixed" cat-option-face)
     (":precondition (and (>= ram ram-req)" ":precondition" cat-option-face)
     (":precondition (and (>= ram ram-req)" "and" cat-operator-face)
     (":precondition (and (>= ram ram-req)" ">=" cat-symbol-operator-face)
     ("(not (member out topics))" "not" cat-operator-face)
     ("(not (member out topics))" "member" cat-operator-face)
     ("(decrease ram ram-req) (add topics out)" "decrease" cat-operator-face)
     ("(decrease ram ram-req) (add topics out)" "add" cat-operator-face)
     ("(:hole mu :view software :max-effects 2)" ":hole" cat-section-face)
     ("(:hole mu :view software :max-effects 2)" ":view" cat-option-face)
     ("(:hole mu :view software :max-effects 2)" ":max-effects" cat-option-face)
     ("(:view software :drop (mounted" ":view" cat-section-face)
     ("(:view software :drop (mounted" ":drop" cat-option-face)
     ("(define (problem p1)" "problem" cat-structure-face)
     ("(:domain detection)" ":domain" cat-section-face)
     ("(:objects fire-extinguisher - class)" "fire-extinguisher" nil)
     ("(:init (= ram 64) (= mounted {camera})" ":init" cat-section-face)
     ("(:init (= ram 64) (= mounted {camera})" "=" cat-symbol-operator-face)
     ("(:init (= ram 64) (= mounted {camera})" "64" cat-number-face)
     ("(:init (= ram 64) (= mounted {camera})" "{camera}" nil)
     ("(= armed false)" "false" cat-constant-face)
     ("(assign armed true)" "assign" cat-operator-face)
     ("(assign armed true)" "true" cat-constant-face)
     ("(armed bool :group safety)" "bool" cat-type-face)
     ("(:soft (>= ram 16) :weight 5)" ":weight" cat-option-face)
     ("(:metric lex (minimize (total-churn)) (maximize ram))" "lex" cat-metric-face)
     ("(:metric lex (minimize (total-churn)) (maximize ram))" "minimize" cat-metric-face)
     ("(:metric lex (minimize (total-churn)) (maximize ram))" "total-churn" cat-operator-face)
     ("(:metric lex (minimize (total-churn)) (maximize ram))" "maximize" cat-metric-face)
     ("  (:view software))" ":view" cat-section-face)
     ("and-gate not-ready total-churn-x x-or camera2 realistic - class)"
      "and-gate not-ready total-churn-x x-or camera2 realistic" nil))))

(ert-deftest cat-mode-test-syntax ()
  "Names with hyphens and :keywords are single symbols; braces are parentheses."
  (cat-mode-test--with-buffer cat-mode-test-sample
    (search-forward ":precondition")
    (should (equal (thing-at-point 'symbol t) ":precondition"))
    (search-forward "ram-req")
    (should (equal (thing-at-point 'symbol t) "ram-req"))
    (search-forward "{")
    (backward-char)
    (forward-sexp)
    (should (eq (char-before) ?}))
    (goto-char (point-min))
    (search-forward "published")
    (should (nth 3 (syntax-ppss)))
    (goto-char (point-min))
    (search-forward "TODO")
    (should (nth 4 (syntax-ppss)))))

(ert-deftest cat-mode-test-comments ()
  "`comment-region' writes `; ' comments, which the syntax table sees as comments."
  (should (equal (with-temp-buffer
                   (cat-mode)
                   (insert "(:horizon 8)\n")
                   (comment-region (point-min) (point-max))
                   (buffer-string))
                 "; (:horizon 8)\n"))
  (cat-mode-test--with-buffer "(:horizon 8) ; eight steps\n"
    (search-forward "eight")
    (should (nth 4 (syntax-ppss)))))

(ert-deftest cat-mode-test-indent-keeps-sample ()
  "Indenting the sample, already indented, changes nothing."
  (cat-mode-test--with-buffer cat-mode-test-sample
    (let ((inhibit-message t))
      (indent-region (point-min) (point-max)))
    (should (equal (buffer-string) cat-mode-test-sample))))

(ert-deftest cat-mode-test-indent-fixes-flat-text ()
  "Indenting the sample with every line flushed left restores its indentation."
  (let ((flat (replace-regexp-in-string "^[ \t]+" "" cat-mode-test-sample)))
    (should-not (equal flat cat-mode-test-sample))
    (cat-mode-test--with-buffer flat
      (let ((inhibit-message t))
        (indent-region (point-min) (point-max)))
      (should (equal (buffer-string) cat-mode-test-sample)))))

(ert-deftest cat-mode-test-imenu ()
  "The imenu index lists domains, problems, morphisms, holes and views."
  (cat-mode-test--with-buffer cat-mode-test-sample
    (let* ((index (imenu--make-index-alist t))
           (names (lambda (group) (mapcar #'car (cdr (assoc group index))))))
      (should (equal (funcall names "Morphisms") '("camera-driver" "person-detector")))
      (should (equal (funcall names "Holes") '("mu")))
      (should (equal (funcall names "Views") '("software")))
      (should (assoc "detection" index))
      (should (assoc "p1" index)))))

(defconst cat-mode-test-contexts
  '(("structure" cat-structure-face "(%s x)")
    ("section" cat-section-face "(%s x)")
    ("option" cat-option-face "(x %s y)")
    ("requirement" cat-requirement-face "(:requirements %s)")
    ("operator" cat-operator-face "(%s x y)")
    ("symbol-operator" cat-symbol-operator-face "(%s x y)")
    ("type" cat-type-face "(x %s)")
    ("constant" cat-constant-face "(= x %s)")
    ("kind" cat-kind-face "(x :kind %s)")
    ("metric" cat-metric-face "(:metric %s x)"))
  "Face and context (%s is the word) of each keyword category.")

(ert-deftest cat-mode-test-every-keyword ()
  "Every word of CAT_KEYWORDS_JSON gets its category's face.
A word glued to more name characters is a plain name: no face."
  (let ((file (getenv "CAT_KEYWORDS_JSON")))
    (when (member file (list nil ""))
      (ert-skip "CAT_KEYWORDS_JSON is not set (tests/editors/test_emacs.py sets it)"))
    (let* ((json-object-type 'alist)
           (json-array-type 'list)
           (json-key-type 'string)
           (keywords (json-read-file file))
           (checks nil)
           (failures nil))
      (should keywords)
      (with-temp-buffer
        (cat-mode)
        (dolist (entry keywords)
          (let ((context (assoc (car entry) cat-mode-test-contexts)))
            (if (null context)
                (push (format "no face known for keyword category %S" (car entry)) failures)
              (dolist (word (cdr entry))
                (let ((line (format (nth 2 context) word)))
                  (push (list line word (nth 1 context)) checks)
                  (insert line "\n"))
                (when (string-match-p "\\`:?[A-Za-z]" word)
                  (let ((glued (concat word "-zz")))
                    (push (list (format "(x %s y)" glued) glued nil) checks)
                    (insert (format "(x %s y)\n" glued)))
                  (unless (string-prefix-p ":" word)
                    (let ((glued (concat "zz-" word)))
                      (push (list (format "(x %s y)" glued) glued nil) checks)
                      (insert (format "(x %s y)\n" glued)))))))))
        (font-lock-ensure)
        (dolist (check (nreverse checks))
          (let ((problem (apply #'cat-mode-test--check check)))
            (when problem (push problem failures)))))
      (should (equal (nreverse failures) nil))
      (should (> (length checks) 0)))))

(provide 'cat-mode-tests)

;;; cat-mode-tests.el ends here
