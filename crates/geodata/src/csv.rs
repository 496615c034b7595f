//! Delimited text tables (RFC 4180 CSV as spreadsheets and GIS export it), read with the `csv`
//! crate: a header row, then one record per line; fields separated by `,`, `;` or tabs
//! (whichever the header uses), optionally quoted with `"` (a doubled `""` inside quotes is one
//! quote), CRLF or LF line ends. A byte order mark, blank lines and lines starting with `#` are
//! skipped; fields are trimmed. A quoted field may not span lines (field tables never
//! need it, and it keeps every record on its own line number, which the errors name).

use csv::{ReaderBuilder, StringRecord};

/// One record: its 1-based line in the file and its fields.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub line: usize,
    pub fields: Vec<String>,
}

/// A parsed table.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub header: Vec<String>,
    pub records: Vec<Record>,
}

/// Why a table was refused: each names the line and, where one field is at fault, its 1-based
/// column; the caller puts the file's name in front.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CsvError {
    #[error("is empty: it needs a header row")]
    Empty,
    #[error("{line}: has {fields} fields, the header {header}")]
    Ragged { line: usize, fields: usize, header: usize },
    #[error("{line}: column {column}: a quoted field is not closed on its line")]
    OpenQuote { line: usize, column: usize },
    #[error("{line}: {reason}")]
    Unreadable { line: usize, reason: String },
}

impl Table {
    /// Parses `text`; errors name the line and column.
    pub fn parse(text: &str) -> Result<Table, CsvError> {
        let delimiter = delimiter(text);
        let mut rows = text
            .split_inclusive('\n')
            .enumerate()
            .filter(|(_, l)| !l.trim_start_matches('\u{feff}').trim().is_empty())
            .filter_map(|(i, l)| Row::read(i + 1, l, delimiter).transpose());
        let header = rows.next().ok_or(CsvError::Empty)??.fields;
        let mut records = Vec::new();
        for row in rows {
            let Row { line, fields } = row?;
            if fields.len() != header.len() {
                return Err(CsvError::Ragged { line, fields: fields.len(), header: header.len() });
            }
            records.push(Record { line, fields });
        }
        Ok(Table { header, records })
    }

    /// The index of the column named `name` (case and surrounding spaces ignored).
    pub fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h.eq_ignore_ascii_case(name.trim()))
    }
}

/// The delimiter the header row uses: `;`, else a tab, else `,`.
fn delimiter(text: &str) -> u8 {
    let header = text
        .trim_start_matches('\u{feff}')
        .lines()
        .find(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .unwrap_or_default();
    [b';', b'\t', b','].into_iter().find(|d| header.as_bytes().contains(d)).unwrap_or(b',')
}

/// One row of fields, with its line.
struct Row {
    line: usize,
    fields: Vec<String>,
}

impl Row {
    /// The fields of `text`, one line with its line end (none for a comment line). Each line is
    /// read on its own so that records and line numbers agree, and a quote still open at the
    /// line end shows as a field holding the line end.
    fn read(line: usize, text: &str, delimiter: u8) -> Result<Option<Row>, CsvError> {
        let mut reader = ReaderBuilder::new()
            .delimiter(delimiter)
            .has_headers(false)
            .flexible(true)
            .comment(Some(b'#'))
            .from_reader(text.as_bytes());
        let mut record = StringRecord::new();
        let read = reader.read_record(&mut record);
        if !read.map_err(|e| CsvError::Unreadable { line, reason: e.to_string() })? {
            return Ok(None);
        }
        if let Some(at) = record.iter().position(|f| f.contains(['\n', '\r'])) {
            return Err(CsvError::OpenQuote { line, column: at + 1 });
        }
        Ok(Some(Row { line, fields: record.iter().map(|f| f.trim().to_string()).collect() }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_quotes_delimiters_and_line_numbers() {
        let text = "\u{feff}name;X;Y\r\n# comment\n\n\"Gouffre; \"\"A\"\"\";651234.5; 6862345\nB;1;2\n";
        let t = Table::parse(text).unwrap();
        assert_eq!(t.header, ["name", "X", "Y"]);
        assert_eq!(
            t.records[0],
            Record { line: 4, fields: vec!["Gouffre; \"A\"".into(), "651234.5".into(), "6862345".into()] }
        );
        assert_eq!(t.records[1].line, 5);
        assert_eq!(t.column("x"), Some(1));
        assert_eq!(Table::parse("a,b\n1,2\n").unwrap().records[0].fields, ["1", "2"]);
        assert_eq!(Table::parse("a\tb\n1\t2\n").unwrap().records[0].fields, ["1", "2"]);
    }

    #[test]
    fn ragged_rows_and_open_quotes_name_their_line() {
        assert_eq!(Table::parse("a,b\n1,2\n3\n").unwrap_err().to_string(), "3: has 1 fields, the header 2");
        assert_eq!(
            Table::parse("a,b\n\"1,2\n").unwrap_err().to_string(),
            "2: column 1: a quoted field is not closed on its line"
        );
        assert!(Table::parse("\n# only a comment\n").unwrap_err().to_string().contains("is empty"));
    }
}
