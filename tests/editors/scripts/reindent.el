;;; reindent.el --- re-indent .cat files with cat-mode  -*- lexical-binding: t -*-
;; Indent every file of $CAT_FILES (one a line) with `indent-region' (after flushing every
;; line left when $CAT_FLUSH is 1) and print one line per file that changes, with its first
;; changed line, then "N differ".  tests/editors/test_emacs.py.
(add-to-list 'load-path (getenv "CAT_EMACS_DIR"))
(require 'cat-mode)
(let ((bad 0) (flush (equal (getenv "CAT_FLUSH") "1")))
  (dolist (f (split-string (getenv "CAT_FILES") "\n" t))
    (with-temp-buffer
      (insert-file-contents f)
      (cat-mode)
      (let ((before (buffer-string)))
        (when flush
          (goto-char (point-min))
          (while (re-search-forward "^[ \t]+" nil t) (replace-match "")))
        (let ((inhibit-message t)) (indent-region (point-min) (point-max)))
        (unless (equal before (buffer-string))
          (setq bad (1+ bad))
          (let ((a (split-string before "\n")) (b (split-string (buffer-string) "\n")) (i 1))
            (while (and a (equal (car a) (car b))) (setq a (cdr a) b (cdr b) i (1+ i)))
            (princ (format "%s:%d: %s\n" f i (car b))))))))
  (princ (format "%d differ\n" bad)))
